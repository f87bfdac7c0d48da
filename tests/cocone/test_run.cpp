// run(): samples PointCloud -> Mesh (field pass-through, order, orientation, empty result).
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>

#include "fixtures/cocone_samples.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "cocone/cocone.h"
#include "mesh_checks.h"

namespace cc = canopy::cocone;
namespace fm = canopy::formats;

namespace {

// The shared Fibonacci sphere with a per-row tag field.
fm::PointCloud ball(int n, double r, double zc) {
  fm::PointCloud c = cocone_test::fibonacci_ball(n, r, zc);
  auto& tag = c.add("tag", fm::kUint32);
  for (int i = 0; i < n; ++i) tag[i] = 1000 + i;
  return c;
}

struct Quiet {
  Quiet() { canopy::common::log::set_level(canopy::common::log::Level::kQuiet); }
};
const Quiet quiet;

}  // namespace

TEST_CASE("raw mesh keeps every sample row and closes the ball") {
  const auto c = ball(1500, 1.0, 1.5);
  cc::Params p;
  p.postprocess = false;
  const auto m = cc::run(p, {&c});
  CHECK(m.vertices.size() == c.size());
  CHECK(m.vertices.names() == c.names());
  CHECK(m.vertices.col("tag") == c.col("tag"));
  CHECK(m.faces.size() == 2 * c.size() - 4);
  CHECK(cocone_test::topology(m.faces).euler() == 2);
}

TEST_CASE("post-processed mesh: surviving rows in input order, every field, faces follow normals") {
  const auto c = ball(1500, 1.0, 1.5);
  const auto m = cc::run(cc::Params{}, {&c});
  REQUIRE(m.faces.size() > 0);
  CHECK(m.vertices.names() == c.names());
  const auto& tag = m.vertices.col("tag");
  const auto& z = m.vertices.col("z");
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const auto row = static_cast<std::size_t>(tag[i]) - 1000;
    CHECK(z[i] == c.col("z")[row]);
    CHECK(z[i] >= 0.3);
    if (i > 0) CHECK(tag[i] > tag[i - 1]);
  }
  const auto& x = m.vertices.col("x");
  const auto& y = m.vertices.col("y");
  const auto& nx = m.vertices.col("normal_x");
  const auto& ny = m.vertices.col("normal_y");
  const auto& nz = m.vertices.col("normal_z");
  std::size_t agree = 0;
  for (const auto& f : m.faces) {
    Eigen::Vector3d p[3], n = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      p[k] = {x[f[k]], y[f[k]], z[f[k]]};
      n += Eigen::Vector3d(nx[f[k]], ny[f[k]], nz[f[k]]);
    }
    agree += (p[1] - p[0]).cross(p[2] - p[0]).dot(n) > 0;
  }
  CHECK(agree == m.faces.size());
  // Every vertex is used (orphans removed).
  CHECK(cocone_test::topology(m.faces).vertices == m.vertices.size());
}

TEST_CASE("Cocone making no triangle at all says so, not that post-processing removed them") {
  // Five samples spread over 3 m (a sparse candidate's few voxels): no cocone triangle (review F14).
  fm::PointCloud c;
  c.add("x") = {0, 3, 0, 3, 1.5};
  c.add("y") = {0, 0, 3, 3, 1.5};
  c.add("z") = {1, 1.5, 2, 1.2, 3};
  c.resize(5);
  for (const bool post : {true, false}) {
    cc::Params p;
    p.postprocess = post;
    CHECK_THROWS_WITH(cc::run(p, {&c}), Catch::Matchers::Contains("Cocone made no triangle from 5 samples") &&
                                            !Catch::Matchers::Contains("post-processing"));
  }
}

TEST_CASE("a mesh with no face left is an error") {
  const auto c = ball(500, 0.1, 0.0);  // entirely below 300 mm
  CHECK_THROWS_WITH(cc::run(cc::Params{}, {&c}), Catch::Matchers::Contains("no triangle left"));
  cc::Params raw;
  raw.postprocess = false;
  CHECK(cc::run(raw, {&c}).faces.size() == 2 * 500 - 4);
}

TEST_CASE("validate: the defaults pass; each bad parameter is a usage error naming its option") {
  CHECK_NOTHROW(cc::validate(cc::Params{}));
  cc::Params p;
  p.cocone.cocone_angle = canopy::common::kPi / 2;
  CHECK_THROWS_WITH(cc::validate(p), Catch::StartsWith("--cocone-angle"));
  p = cc::Params{};
  p.cocone.flat_ratio = 0;
  CHECK_THROWS_WITH(cc::validate(p), Catch::StartsWith("--flat-ratio"));
  p = cc::Params{};
  p.post.max_aspect = 0.5;
  CHECK_THROWS_WITH(cc::validate(p), Catch::StartsWith("--max-aspect"));
  p = cc::Params{};
  p.post.min_height = -1;
  CHECK_THROWS_AS(cc::validate(p), canopy::common::UsageError);
}
