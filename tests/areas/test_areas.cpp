// areas: the estimators on hand-built point sets, meshes and segment graphs of known area.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <cmath>

#include "areas/areas.h"
#include "canopy/common/error.h"

using namespace canopy;
using Eigen::Vector3d;

namespace {

// One orthographic view of a plane through the origin with unit normal n, seen along -toward:
// pixel centres on a square grid of `spacing` perpendicular to the view, projected onto the
// plane, kept inside the plane's square of half-size `half` (in plane coordinates).
std::vector<areas::ScanPoint> view_of_plane(const Vector3d& n, const Vector3d& toward, double spacing, double half,
                                            int view, double offset) {
  const Vector3d d = toward.normalized();
  const Vector3d a = d.unitOrthogonal(), b = d.cross(a);
  const Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  std::vector<areas::ScanPoint> out;
  const int m = static_cast<int>(4 * half / spacing);
  for (int i = -m; i <= m; ++i) {
    for (int j = -m; j <= m; ++j) {
      const Vector3d ray = (i + offset) * spacing * a + (j + offset) * spacing * b;
      const double t = -ray.dot(n) / d.dot(n);  // ray + t d on the plane
      const Vector3d p = ray + t * d;
      if (std::abs(p.dot(e1)) <= half && std::abs(p.dot(e2)) <= half) out.push_back({p, d, view});
    }
  }
  return out;
}

}  // namespace

TEST_CASE("visible area of a tilted square seen by one and by three overlapping views") {
  const Vector3d n = Vector3d(0.3, -0.2, 1).normalized();
  const double half = 1.0, truth = 4.0;  // a 2 m square
  auto one = view_of_plane(n, Vector3d(0.1, 0.2, 1), 0.03, half, 0, 0.5);
  CHECK(areas::visible_area(one, 0.03, 0.045) == Approx(truth).epsilon(0.03));
  // Three views of the same square: the union is still the square, not three times it.
  auto all = one;
  for (const auto& p : view_of_plane(n, Vector3d(-0.6, 0.3, 1), 0.03, half, 1, 0.25)) all.push_back(p);
  for (const auto& p : view_of_plane(n, Vector3d(0.2, -0.7, 1), 0.03, half, 2, 0.1)) all.push_back(p);
  CHECK(areas::visible_area(all, 0.03, 0.045) == Approx(truth).epsilon(0.04));
}

TEST_CASE("samples stand for h^2 / |n|_1 each") {
  const std::vector<Vector3d> normals = {Vector3d::UnitZ(), Vector3d(1, 1, 0), -Vector3d::UnitX()};
  CHECK(areas::samples_area(normals, 0.1) == Approx(0.01 + 0.01 / std::sqrt(2.0) + 0.01));
}

TEST_CASE("mesh target area counts each triangle by its share of target vertices") {
  formats::Mesh m;
  m.vertices.add("x", formats::kFloat32);
  m.vertices.add("y", formats::kFloat32);
  m.vertices.add("z", formats::kFloat32);
  m.vertices.add("label", formats::kUint32);
  m.vertices.resize(4);
  // Unit square split into two right triangles of 0.5 m²; vertex 3 is foliage.
  const double xs[] = {0, 1, 1, 0}, ys[] = {0, 0, 1, 1}, labels[] = {1, 1, 1, 2};
  for (std::size_t i = 0; i < 4; ++i) {
    m.vertices.col("x")[i] = xs[i];
    m.vertices.col("y")[i] = ys[i];
    m.vertices.col("z")[i] = 0;
    m.vertices.col("label")[i] = labels[i];
  }
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  CHECK(areas::mesh_area(m, 1) == Approx(0.5 + 0.5 * 2.0 / 3.0));
  CHECK(areas::mesh_area(m, 2) == Approx(0.5 / 3.0));
}

TEST_CASE("segment target area, all segments and the X largest") {
  formats::SegmentGraph g;
  auto seg = [](int id, double area, int label, double purity) {
    formats::Segment s;
    s.segment_id = id;
    s.area = area;
    s.label = label;
    s.label_purity = purity;
    return s;
  };
  g.segments = {seg(0, 1.0, 1, 1.0), seg(1, 3.0, 2, 0.9), seg(2, 2.0, 1, 0.5), seg(3, 2.0, 1, 1.0)};
  CHECK(areas::segments_area(g, 1, 0) == Approx(1.0 + 1.0 + 2.0));
  CHECK(areas::segments_area(g, 1, 2) == Approx(1.0));        // segments 1 (foliage) and 2 (tie: lower id)
  CHECK(areas::segments_area(g, 1, 3) == Approx(1.0 + 2.0));  // + segment 3
}

TEST_CASE("areas.json round trip and a foreign document named") {
  areas::Areas a;
  a.visible = 44.5;
  a.samples = 23.25;
  a.mesh = 21;
  a.segments = 20.5;
  a.matched = 18.75;
  a.spacing = 0.03;
  a.cell = 0.045;
  a.voxel = 0.128;
  a.max_segments = 15;
  a.target_points = 1234;
  a.target_samples = 321;
  const areas::Areas b = areas::parse(areas::serialize(a, {"scan.pcd"}), "a.json");
  CHECK(b.visible == a.visible);
  CHECK(b.matched == a.matched);
  CHECK(b.cell == a.cell);
  CHECK(b.target_samples == a.target_samples);
  CHECK_THROWS_AS(areas::parse("{\"format\": \"canopy.segment_graph\", \"version\": 1}", "x.json"),
                  common::DataError);
  CHECK_THROWS_AS(areas::parse("not json", "y.json"), common::DataError);
}
