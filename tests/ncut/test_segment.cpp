// Segmentation of synthetic meshes with known faces, and segment attributes.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <set>

#include "fixtures/ncut_meshes.h"
#include "ncut/ncut.h"

using namespace canopy::ncut;
using namespace canopy::ncut::testing;
using Eigen::Vector3d;

namespace {

// Every ground-truth part maps to exactly one segment and vice versa.
void check_parts_are_segments(const std::vector<int>& part, const std::vector<int>& segment) {
  std::map<int, std::set<int>> seg_of_part, part_of_seg;
  for (std::size_t v = 0; v < part.size(); ++v) {
    seg_of_part[part[v]].insert(segment[v]);
    part_of_seg[segment[v]].insert(part[v]);
  }
  for (const auto& [p, segs] : seg_of_part) {
    INFO("part " << p);
    CHECK(segs.size() == 1);
  }
  for (const auto& [s, parts] : part_of_seg) {
    INFO("segment " << s);
    CHECK(parts.size() == 1);
  }
}

}  // namespace

TEST_CASE("affinity: Eq. 5.8 distance and Eq. 5.11/5.12 values by hand") {
  SurfacePoints pts;
  pts.p = {{0, 0, 0}, {0.3, 0, 0.1}};
  pts.n = {{0, 0, 1}, {std::sin(0.1), 0, std::cos(0.1)}};  // 0.1 rad apart
  // From 0: v = (-0.3, 0, -0.1), v.n0 = -0.1, tangential 0.3.
  CHECK(anisotropic_distance(pts.p[0], pts.n[0], pts.p[1], 2.0) == Approx(std::sqrt(2 * 0.01 + 0.09 / 2)));
  ThesisAffinityParams prm;
  prm.exponent = Exponent::kSquared;
  ThesisAffinity sq(pts, prm);
  const double s2 = 2 * prm.sigma_n * prm.sigma_n, r2 = 2 * 0.512 * 0.512;
  const double d01 = anisotropic_distance(pts.p[0], pts.n[0], pts.p[1], 2.0);
  const double d10 = anisotropic_distance(pts.p[1], pts.n[1], pts.p[0], 2.0);
  CHECK(sq.one_sided(0, 1) == Approx(std::exp(-0.01 / s2) * std::exp(-d01 * d01 / r2)));
  CHECK(sq(0, 1) == Approx(std::min(sq.one_sided(0, 1), sq.one_sided(1, 0))));
  CHECK(sq(0, 1) == sq(1, 0));
  prm.exponent = Exponent::kLinear;
  ThesisAffinity lin(pts, prm);
  CHECK(lin.one_sided(1, 0) == Approx(std::exp(-0.1 / s2) * std::exp(-1000 * d10 / (2 * 512.0 * 512.0))));
}

TEST_CASE("sparsification: radius, random share, threshold, mesh neighbours kept") {
  // A row of points 0.1 m apart with identical normals, and one far mesh neighbour.
  SurfacePoints pts;
  for (int i = 0; i < 12; ++i) {
    pts.p.push_back({0.1 * i, 0, 0});
    pts.n.push_back({0, 0, 1});
  }
  pts.p.push_back({0, 0, 2.0});  // 12: 2 m above vertex 0, normal tilted 90 deg
  pts.n.push_back({1, 0, 0});
  ThesisAffinityParams ap;
  ThesisAffinity aff(pts, ap);
  SparsifyParams sp;
  GraphStats st;
  const Graph g = build_affinity_graph(pts, {{0, 12}}, aff, sp, &st);
  auto has = [&](int a, int b) { return std::find(g.nbr_begin(a), g.nbr_end(a), b) != g.nbr_end(a); };
  for (int i = 0; i < 12; ++i) {
    for (int j = i + 1; j < 12; ++j) {
      const double d = 0.1 * (j - i);
      if (d > 0.512 + 1e-9) CHECK_FALSE(has(i, j));
      if (d < 0.175) CHECK(has(i, j));  // close, similar normal: always kept
    }
  }
  CHECK(has(0, 12));  // forced mesh edge beyond r
  CHECK(st.mesh_edges_forced == 1);
  // Its affinity (90 deg apart, 2 m away) is ~1e-11; the floor keeps it usable.
  auto weight = [](const Graph& gr, int a, int b) {
    const int* nb = gr.nbr_begin(a);
    const double* w = gr.w_begin(a);
    for (; nb != gr.nbr_end(a); ++nb, ++w) {
      if (*nb == b) return *w;
    }
    return -1.0;
  };
  CHECK(aff(0, 12) < 1e-6);
  CHECK(weight(g, 0, 12) == sp.mesh_edge_floor);
  CHECK(weight(g, 0, 1) == Approx(aff(0, 1)));  // ordinary edges are not floored
  SparsifyParams no_floor = sp;
  no_floor.mesh_edge_floor = 0;
  CHECK(weight(build_affinity_graph(pts, {{0, 12}}, aff, no_floor, nullptr), 0, 12) == aff(0, 12));
  // Roughly a quarter of the pairs between 175 mm and r survive.
  CHECK(st.dropped_random > 0);
  sp.keep_fraction = 1.0;
  const Graph all = build_affinity_graph(pts, {{0, 12}}, aff, sp, nullptr);
  CHECK(all.edge_count() > g.edge_count());
  sp.keep_mesh_edges = false;
  const Graph no_mesh = build_affinity_graph(pts, {{0, 12}}, aff, sp, nullptr);
  CHECK(no_mesh.degree(12) == 0);
}

TEST_CASE("two planes meeting at 90 degrees give two segments") {
  for (Exponent e : {Exponent::kSquared, Exponent::kLinear}) {
    TestMesh m = two_planes(1.0, 0.1);
    Params p;
    p.affinity.exponent = e;
    const Result r = run(p, m.in);
    CHECK(r.graph.segments.size() == 2);
    check_parts_are_segments(m.part, r.segment);
    REQUIRE(r.graph.adjacency.size() == 1);
    CHECK(r.graph.adjacency[0].a == 0);
    CHECK(r.graph.adjacency[0].b == 1);
    CHECK(r.graph.adjacency[0].shared_edges == 2 * 10 - 1);  // the zipped ladder's cross edges
  }
}

TEST_CASE("a sampled box's faces come out as separate segments") {
  TestMesh m = box({2.0, 1.2, 0.8}, 0.1);
  Params p;
  const Result r = run(p, m.in);
  CHECK(r.graph.segments.size() == 6);
  check_parts_are_segments(m.part, r.segment);
  // Each segment's normal is its face's outward normal.
  for (const auto& s : r.graph.segments) {
    const int part = m.part[s.vertices[0]];
    Vector3d want = Vector3d::Zero();
    want[part / 2] = part % 2 ? 1 : -1;
    CHECK(Vector3d(s.normal[0], s.normal[1], s.normal[2]).dot(want) == Approx(1.0).margin(1e-9));
  }
  // Each face touches the four faces around it (12 box edges).
  CHECK(r.graph.adjacency.size() == 12);

  SECTION("with noise: 4 mm positions, ~2 deg normals") {
    add_noise(&m, 0.004, 0.025, 3);
    const Result rn = run(p, m.in);
    CHECK(rn.graph.segments.size() == 6);
    check_parts_are_segments(m.part, rn.segment);
  }
}

TEST_CASE("same input and seed give identical labels; the seed changes only the graph") {
  TestMesh m = box({1.6, 1.0, 0.7}, 0.1, false);
  add_noise(&m, 0.002, 0.02, 9);
  Params p;
  p.sparsify.seed = 42;
  const Result a = run(p, m.in);
  const Result b = run(p, m.in);
  CHECK(a.segment == b.segment);
  CHECK(a.stats.graph.edges == b.stats.graph.edges);
  CHECK(a.stats.cut.matvecs == b.stats.cut.matvecs);
  p.sparsify.seed = 43;
  const Result c = run(p, m.in);
  CHECK(c.stats.graph.dropped_random != a.stats.graph.dropped_random);
  check_parts_are_segments(m.part, c.segment);  // open box: 5 faces either way
  CHECK(c.graph.segments.size() == 5);
}

TEST_CASE("segment attributes of a known rectangle") {
  // 2.0 m x 0.5 m rectangle in the plane z = 1, tilted normal up, sampled at 0.05 m.
  TestMesh m;
  m.add_grid({0, 0, 1}, {2.0, 0, 0}, {0, 0.5, 0}, 40, 10, {0, 0, 1}, 0);
  for (auto& l : m.part) (void)l;
  m.in.labels.assign(m.in.points.size(), 1);
  for (int k = 0; k < 10; ++k) m.in.labels[k] = 2;  // first column: foliage
  std::vector<int> one(m.in.points.size(), 0);
  const auto normals = m.in.normals;

  // The samples cover [0.025, 1.975] x [0.025, 0.475]: sides 1.95 x 0.45.
  const double a = 1.95, b = 0.45;
  const auto s = segment_attributes(m.in, normals, one, 1, PcaWeighting::kSurface)[0];
  CHECK(s.area == Approx(a * b).epsilon(1e-12));
  CHECK(s.thickness == Approx(0).margin(1e-7));
  CHECK(s.elongation == Approx(b / a).epsilon(1e-9));
  CHECK(s.radii[0] == Approx(a / std::sqrt(12.0)).epsilon(1e-9));
  CHECK(s.radii[1] == Approx(b / std::sqrt(12.0)).epsilon(1e-9));
  CHECK(s.centroid[0] == Approx(1.0));
  CHECK(s.centroid[1] == Approx(0.25));
  CHECK(s.centroid[2] == Approx(1.0));
  CHECK(s.normal[2] == Approx(1.0));
  CHECK(s.vertex_count == 400);
  CHECK(s.label == 1);
  // Foliage column: 10 vertices on the short boundary own half-width cells (corners less).
  const double h = a / 39, k = b / 9;
  const double foliage = (8 * 0.5 * h * k + 2 * 0.25 * h * k);
  CHECK(s.label_purity == Approx(1 - foliage / (a * b)).epsilon(1e-9));

  // Flipped input normals flip the segment normal.
  std::vector<Vector3d> down(normals.size(), Vector3d(0, 0, -1));
  CHECK(segment_attributes(m.in, down, one, 1, PcaWeighting::kSurface)[0].normal[2] == Approx(-1.0));

  // Vertex weighting: the discrete variance of 40 and 10 evenly spaced samples.
  const auto sv = segment_attributes(m.in, normals, one, 1, PcaWeighting::kVertices)[0];
  const double vx = h * h * (40 * 40 - 1) / 12.0, vy = k * k * (10 * 10 - 1) / 12.0;
  CHECK(sv.elongation == Approx(std::sqrt(vy / vx)).epsilon(1e-9));
  CHECK(sv.thickness == Approx(0).margin(1e-7));
}

TEST_CASE("missing normals are computed from the faces") {
  TestMesh m = two_planes(1.0, 0.1);
  const auto given = m.in.normals;
  const auto computed = vertex_normals(m.in.points, m.in.faces);
  // Interior vertices of the floor: the face normal (up to the winding's sign).
  CHECK(std::abs(computed[5 * 10 + 5].dot(given[5 * 10 + 5])) == Approx(1.0));
  m.in.normals.clear();
  const Result r = run(Params{}, m.in);
  CHECK(r.stats.normals_computed);
  CHECK(r.graph.segments.size() >= 2);
  for (const auto& s : r.graph.segments) CHECK(std::isfinite(s.normal[0]));
}

TEST_CASE("segment colours are fixed and distinct for neighbouring ids") {
  CHECK(segment_colour(3) == segment_colour(3));
  std::set<std::array<std::uint8_t, 3>> seen;
  for (int id = 0; id < 30; ++id) seen.insert(segment_colour(id));
  CHECK(seen.size() == 30);
}

TEST_CASE("validate: the defaults pass; each bad parameter is a usage error naming its option") {
  CHECK_NOTHROW(validate(Params{}));
  Params p;
  p.affinity.radius = 0;
  CHECK_THROWS_WITH(validate(p), Catch::StartsWith("--radius"));
  p = Params{};
  p.sparsify.keep_fraction = 2;
  CHECK_THROWS_WITH(validate(p), Catch::StartsWith("--keep-fraction"));
  p = Params{};
  p.cut.ncv = 2;
  CHECK_THROWS_WITH(validate(p), Catch::StartsWith("--ncv"));
}

TEST_CASE("the affinity's radius is the graph's cut-off (one radius)") {
  SurfacePoints pts;
  for (int i = 0; i < 5; ++i) {
    pts.p.push_back({0.2 * i, 0, 0});
    pts.n.push_back({0, 0, 1});
  }
  ThesisAffinityParams ap;
  ap.radius = 0.3;  // neighbours at 0.2 m only
  const ThesisAffinity aff(pts, ap);
  CHECK(aff.radius() == 0.3);
  SparsifyParams sp;
  sp.dense_radius = 1;
  sp.min_affinity = 0;
  sp.keep_mesh_edges = false;
  GraphStats st;
  build_affinity_graph(pts, {}, aff, sp, &st);
  CHECK(st.pairs_within_radius == 4);
  ap.radius = 0.5;  // and at 0.4 m
  build_affinity_graph(pts, {}, ThesisAffinity(pts, ap), sp, &st);
  CHECK(st.pairs_within_radius == 7);
}

TEST_CASE("zero-area input and segments are refused, naming the mesh (issue 25)") {
  // Every face degenerate (all vertices at one point: the round-3 reproducer's shape).
  canopy::formats::Mesh flat;
  for (const char* f : {"x", "y", "z"}) flat.vertices.add(f, canopy::formats::kFloat32);
  flat.vertices.resize(4);
  for (std::size_t i = 0; i < 4; ++i) flat.vertices.col("x")[i] = 1, flat.vertices.col("y")[i] = 1;
  flat.faces = {{0, 1, 2}, {1, 2, 3}};
  CHECK_THROWS_WITH(input_from_mesh(flat, "same.ply"),
                    Catch::Contains("same.ply: all 2 faces have zero area"));
  // Collinear vertices: zero area too.
  for (std::size_t i = 0; i < 4; ++i) flat.vertices.col("x")[i] = static_cast<double>(i);
  CHECK_THROWS_WITH(input_from_mesh(flat, "line.ply"),
                    Catch::Contains("line.ply: all 2 faces have zero area"));
  // One real triangle: accepted.
  flat.vertices.col("y")[2] = 2;
  CHECK(input_from_mesh(flat, "ok.ply").faces.size() == 2);

  // A plane plus one vertex in no face, 50 m away: that vertex becomes a segment of its own with
  // no area, which gmatch and the segment graph's readers refuse.
  TestMesh m = two_planes(1.0, 0.1);
  m.in.points.push_back({50, 50, 50});
  m.in.normals.push_back({0, 0, 1});
  const Result r = run(Params{}, m.in);
  REQUIRE(r.graph.segments.size() == 3);
  CHECK(r.graph.segments[2].vertex_count == 1);
  CHECK(r.graph.segments[2].area == 0);
  CHECK_THROWS_WITH(check_segments(r, "orphan.ply"),
                    Catch::Contains("orphan.ply: segment 2 (1 vertices) has zero area"));
  CHECK_NOTHROW(check_segments(run(Params{}, two_planes(1.0, 0.1).in), "planes.ply"));
}
