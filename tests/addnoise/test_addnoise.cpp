// addnoise: requested sigma per axis (within sampling error), every other field kept,
// sigma 0 = exact copy, seeded.
#include <catch2/catch.hpp>

#include <cmath>

#include "addnoise/addnoise.h"
#include "canopy/common/error.h"
#include "canopy/common/rng.h"
#include "canopy/formats/pcd.h"

using namespace canopy;

namespace {

formats::PointCloud scan(std::size_t n) {
  formats::PointCloud c;
  c.resize(n);
  common::Rng rng(5);
  for (const char* f : {"x", "y", "z", "sensor_x", "sensor_y", "sensor_z"}) {
    auto& col = c.add(f, formats::kFloat32);
    for (auto& v : col) v = rng.uniform(-3, 3);
  }
  auto& view = c.add("view_idx", formats::kInt32);
  auto& label = c.add("label", formats::kUint32);
  for (std::size_t i = 0; i < n; ++i) {
    view[i] = static_cast<double>(i % 12);
    label[i] = static_cast<double>(1 + i % 3);
  }
  c.comments.push_back("test scan");
  return c;
}

}  // namespace

TEST_CASE("addnoise: sigma per axis within sampling error, other fields kept") {
  const std::size_t n = 200000;
  const formats::PointCloud in = scan(n);
  addnoise::Params p;
  p.sigma = 0.008;
  p.seed = 7;
  const formats::PointCloud out = addnoise::run(p, {&in});
  REQUIRE(out.size() == n);
  REQUIRE(out.names() == in.names());
  for (const char* f : {"x", "y", "z"}) {
    double sum = 0, sum2 = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = out.col(f)[i] - in.col(f)[i];
      sum += d;
      sum2 += d * d;
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    // Standard errors: mean sigma/sqrt(n) = 1.8e-5, sd sigma/sqrt(2n) = 1.3e-5; allow 5 SE.
    CHECK(std::abs(mean) < 5 * 0.008 / std::sqrt(n));
    CHECK(std::abs(sd - 0.008) < 5 * 0.008 / std::sqrt(2.0 * n));
  }
  for (const char* f : {"sensor_x", "sensor_y", "sensor_z", "view_idx", "label"}) {
    CHECK(out.col(f) == in.col(f));
    CHECK(out.type(f) == in.type(f));
  }
  // Axes independent: correlation of x and y noise near 0.
  double sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxy += (out.col("x")[i] - in.col("x")[i]) * (out.col("y")[i] - in.col("y")[i]);
  }
  CHECK(std::abs(sxy / n / (0.008 * 0.008)) < 5 / std::sqrt(n));
}

TEST_CASE("addnoise: sigma 0 is an exact copy; seeds reproduce") {
  const formats::PointCloud in = scan(1000);
  addnoise::Params p;
  CHECK(formats::serialize_pcd(addnoise::run(p, {&in})) == formats::serialize_pcd(in));
  p.sigma = 0.004;
  p.seed = 3;
  const auto a = formats::serialize_pcd(addnoise::run(p, {&in}));
  CHECK(a == formats::serialize_pcd(addnoise::run(p, {&in})));
  p.seed = 4;
  CHECK(a != formats::serialize_pcd(addnoise::run(p, {&in})));
}

TEST_CASE("validate: sigma in [0, 100 m], the error names --sigma") {
  addnoise::Params p;
  CHECK_NOTHROW(addnoise::validate(p));
  p.sigma = -0.001;
  CHECK_THROWS_WITH(addnoise::validate(p), Catch::StartsWith("--sigma"));
  p.sigma = std::nan("");
  CHECK_THROWS_AS(addnoise::validate(p), common::UsageError);
}
