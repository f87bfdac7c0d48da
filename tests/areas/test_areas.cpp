// areas: the estimators on hand-built point sets, meshes and segment graphs of known area.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "areas/areas.h"
#include "canopy/common/error.h"

using namespace canopy;
using Eigen::Vector3d;

namespace {

// One orthographic view of a plane through the origin with unit normal n, seen along -toward:
// pixel centres on a square grid of `spacing` perpendicular to the view, projected onto the
// plane, kept inside the plane's square of half-size `half` (in plane coordinates).
std::vector<areas::ScanPoint> view_of_plane(const Vector3d& n, const Vector3d& toward, double spacing,
                                            double half, int view, double offset) {
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
  documents::SegmentGraph g;
  auto seg = [](int id, double area, int label, double purity) {
    documents::Segment s;
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

TEST_CASE("validate: the cell is bounded by the spacing (round 3: --cell 1e-6 gave 101.84 m² for 16.35)") {
  areas::Params p;
  CHECK_NOTHROW(areas::validate(p));
  p.cell = 1e-6;
  CHECK_THROWS_WITH(areas::validate(p), Catch::Contains("--cell must be in [--spacing, 4 x --spacing]"));
  p.cell = p.spacing;
  CHECK_NOTHROW(areas::validate(p));
  p.cell = 4 * p.spacing;
  CHECK_NOTHROW(areas::validate(p));
  p.cell = 4.01 * p.spacing;
  CHECK_THROWS_WITH(areas::validate(p), Catch::Contains("--cell"));
  p = areas::Params{};
  for (double spacing : {1e-4, 20.0}) {
    p.spacing = spacing;
    p.cell = 1.5 * spacing;
    CHECK_THROWS_WITH(areas::validate(p), Catch::Contains("--spacing must be in [1mm, 10m]"));
  }
  p = areas::Params{};
  p.voxel = 1e9;
  CHECK_THROWS_WITH(areas::validate(p), Catch::Contains("--voxel"));
  p = areas::Params{};
  p.max_segments = areas::kMaxSegments + 1;
  CHECK_THROWS_WITH(areas::validate(p), Catch::Contains("--max-segments"));
  // Why: three overlapping views of a 4 m² square. At the bounds the estimate holds; with a
  // cell far below the spacing every point is its own neighbourhood and the views' footprints
  // add up (9.66 m² here).
  const Vector3d n = Vector3d(0.3, -0.2, 1).normalized();
  auto all = view_of_plane(n, Vector3d(0.1, 0.2, 1), 0.03, 1.0, 0, 0.5);
  for (const auto& q : view_of_plane(n, Vector3d(-0.6, 0.3, 1), 0.03, 1.0, 1, 0.25)) all.push_back(q);
  for (const auto& q : view_of_plane(n, Vector3d(0.2, -0.7, 1), 0.03, 1.0, 2, 0.1)) all.push_back(q);
  CHECK(areas::visible_area(all, 0.03, 0.03) == Approx(4.0).epsilon(0.1));
  CHECK(areas::visible_area(all, 0.03, 0.12) == Approx(4.0).epsilon(0.1));
  CHECK(areas::visible_area(all, 0.03, 1e-6) > 2 * 4.0);
}

TEST_CASE("run: every stage's target area from one trial's artifacts; missing fields named") {
  areas::Inputs in;
  // Scan: a 1 m x 1 m target plane z = 0 seen from above (view 0), one point per 30 mm pixel,
  // and one foliage point that must not count.
  const auto view = view_of_plane(Vector3d::UnitZ(), Vector3d::UnitZ(), 0.03, 0.5, 0, 0.5);
  for (const char* f : {"x", "y", "z", "sensor_x", "sensor_y", "sensor_z", "view_idx", "label"})
    in.scan.add(f);
  in.scan.resize(view.size() + 1);
  for (std::size_t i = 0; i <= view.size(); ++i) {
    const Vector3d p = i < view.size() ? view[i].p : Vector3d(0, 0, 3);
    in.scan.col("x")[i] = p.x();
    in.scan.col("y")[i] = p.y();
    in.scan.col("z")[i] = p.z();
    in.scan.col("sensor_z")[i] = 1;
    in.scan.col("label")[i] = i < view.size() ? 1 : 2;
  }
  in.scan_name = "scan.pcd";
  // Samples: two target samples facing up, one foliage sample.
  for (const char* f : {"normal_x", "normal_y", "normal_z", "label"}) in.samples.add(f);
  in.samples.resize(3);
  in.samples.col("normal_z") = {1, 1, 1};
  in.samples.col("label") = {1, 2, 1};
  in.samples_name = "samples.pcd";
  for (const char* f : {"x", "y", "z", "label"}) in.mesh.vertices.add(f);
  in.mesh.vertices.resize(3);
  in.mesh.vertices.col("x") = {0, 1, 0};
  in.mesh.vertices.col("y") = {0, 0, 1};
  in.mesh.vertices.col("label") = {1, 1, 1};
  in.mesh.faces = {{0, 1, 2}};
  in.mesh_name = "mesh.ply";
  documents::Segment s;
  s.area = 0.5;
  s.label = 1;
  s.label_purity = 1;
  in.segments.segments = {s};
  areas::Params p;
  p.voxel = 0.1;
  const areas::Areas a = areas::run(p, in);
  CHECK(a.target_points == view.size());
  // Facing the sensor, each pixel stands for spacing² (34 x 34 pixel centres fall in the square).
  CHECK(view.size() == 34 * 34);
  CHECK(a.visible == Approx(34 * 34 * 0.03 * 0.03));
  CHECK(a.target_samples == 2);
  CHECK(a.samples == Approx(2 * 0.01));
  CHECK(a.mesh == Approx(0.5));
  CHECK(a.segments == Approx(0.5));
  CHECK(a.matched == Approx(0.5));
  CHECK(a.voxel == 0.1);
  // A segment graph with a negative area (round 3: "segments": -1e+308 was written), a purity
  // above 1, or areas summing beyond double's range: refused naming the graph.
  in.segments_name = "segments.json";
  in.segments.segments[0].area = -1e308;
  CHECK_THROWS_WITH(areas::run(p, in), Catch::Contains("segments.json: segment 0 has area -1e+308"));
  in.segments.segments[0].area = 0.5;
  in.segments.segments[0].label_purity = 2;
  CHECK_THROWS_WITH(areas::run(p, in), Catch::Contains("segments.json: segment 0 has label_purity 2"));
  in.segments.segments[0].label_purity = 1;
  in.segments.segments[0].area = 1.7e308;
  in.segments.segments.push_back(in.segments.segments[0]);
  CHECK_THROWS_WITH(areas::run(p, in), Catch::Contains("segments.json") && Catch::Contains("beyond"));
  in.segments.segments = {s};
  CHECK(areas::run(p, in).segments == Approx(0.5));
  in.samples.remove("label");
  CHECK_THROWS_WITH(areas::run(p, in), Catch::Contains("samples.pcd") && Catch::Contains("label"));
  p.max_segments = 0;
  CHECK_THROWS_WITH(areas::validate(p), Catch::Contains("--max-segments"));
}
