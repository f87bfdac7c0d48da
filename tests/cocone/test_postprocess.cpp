// Thesis §4.5 post-processing rules on hand-built meshes.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cmath>

#include "cocone/cocone.h"

namespace cc = canopy::cocone;
using V3 = Eigen::Vector3d;

namespace {

// Isosceles triangle at height z with base `base` on the x axis starting at x0 and legs of
// length `leg`: aspect ratio = max(leg, base) / min(leg, base).
void isosceles(std::vector<V3>& p, std::vector<cc::Face>& f, double x0, double base, double leg, double z = 1) {
  const int i = static_cast<int>(p.size());
  p.emplace_back(x0, 0, z);
  p.emplace_back(x0 + base, 0, z);
  p.emplace_back(x0 + base / 2, std::sqrt(leg * leg - base * base / 4), z);
  f.push_back({i, i + 1, i + 2});
}

}  // namespace

TEST_CASE("rule 1+2: low vertices go, and so do the facets they leave with < 3 vertices") {
  // Two triangles sharing an edge; vertex 3 is 0.2 m above ground.
  std::vector<V3> p{{0, 0, 1}, {0.1, 0, 1}, {0, 0.1, 1}, {0.1, 0.1, 0.2}};
  std::vector<cc::Face> f{{0, 1, 2}, {1, 3, 2}};
  const auto r = cc::postprocess(p, f, cc::PostParams{});
  CHECK(r.stats.low_vertices == 1);
  CHECK(r.stats.partial_facets == 1);
  CHECK(r.stats.orphan_vertices == 0);
  CHECK(r.kept == std::vector<std::size_t>{0, 1, 2});
  CHECK(r.faces == std::vector<cc::Face>{{0, 1, 2}});

  // The threshold is z < min_height: exactly 0.3 m stays; 0 disables the rule.
  p[3].z() = 0.3;
  CHECK(cc::postprocess(p, f, cc::PostParams{}).stats.low_vertices == 0);
  p[3].z() = -0.5;
  cc::PostParams off;
  off.min_height = 0;
  off.max_area = 0;
  off.max_aspect = 0;
  const auto r0 = cc::postprocess(p, f, off);
  CHECK(r0.stats.low_vertices == 0);
  CHECK(r0.faces.size() == 2);
}

TEST_CASE("rule 3: facets of area >= max_area go") {
  std::vector<V3> p{{0, 0, 1}, {0.5, 0, 1},  {0, 0.5, 1},    // area 0.125 exactly
                    {1, 0, 1}, {1.25, 0, 1}, {1, 0.25, 1}};  // area 0.03125
  std::vector<cc::Face> f{{0, 1, 2}, {3, 4, 5}};
  cc::PostParams prm;
  prm.max_area = 0.125;
  const auto r = cc::postprocess(p, f, prm);
  CHECK(r.stats.large_facets == 1);
  CHECK(r.faces == std::vector<cc::Face>{{0, 1, 2}});  // reindexed: rows 3, 4, 5
  CHECK(r.kept == std::vector<std::size_t>{3, 4, 5});
  CHECK(r.stats.orphan_vertices == 3);
  // Thesis default 0.04 m^2: the 0.125 triangle goes, the 0.03125 one stays.
  const auto d = cc::postprocess(p, f, cc::PostParams{});
  CHECK(d.stats.large_facets == 1);
  prm.max_area = 0;
  CHECK(cc::postprocess(p, f, prm).faces.size() == 2);
}

TEST_CASE("rule 4: facets with longest/shortest edge > max_aspect go") {
  std::vector<V3> p;
  std::vector<cc::Face> f;
  isosceles(p, f, 0, 0.1, 0.17);  // aspect 1.70: stays
  isosceles(p, f, 1, 0.1, 0.18);  // aspect 1.80: goes
  isosceles(p, f, 2, 0.18, 0.1);  // flat: aspect 1.80, goes
  isosceles(p, f, 3, 0.1, 0.1);   // equilateral: stays
  const auto r = cc::postprocess(p, f, cc::PostParams{});
  CHECK(r.stats.sliver_facets == 2);
  CHECK(r.stats.large_facets == 0);
  REQUIRE(r.faces.size() == 2);
  CHECK(r.kept == std::vector<std::size_t>{0, 1, 2, 9, 10, 11});
  CHECK(r.faces[1] == cc::Face{3, 4, 5});
  cc::PostParams off;
  off.max_aspect = 0;
  CHECK(cc::postprocess(p, f, off).faces.size() == 4);
  // A degenerate facet (zero-length edge) has infinite aspect ratio.
  std::vector<V3> q{{0, 0, 1}, {0, 0, 1}, {0.1, 0, 1}};
  CHECK(cc::postprocess(q, {{0, 1, 2}}, cc::PostParams{}).stats.sliver_facets == 1);
}

TEST_CASE("rule 5: vertices in no facet go unless kept on request") {
  std::vector<V3> p{{5, 5, 5}, {0, 0, 1}, {0.1, 0, 1}, {0, 0.1, 1}, {7, 7, 7}};
  std::vector<cc::Face> f{{1, 2, 3}};
  const auto r = cc::postprocess(p, f, cc::PostParams{});
  CHECK(r.stats.orphan_vertices == 2);
  CHECK(r.kept == std::vector<std::size_t>{1, 2, 3});
  CHECK(r.faces == std::vector<cc::Face>{{0, 1, 2}});
  cc::PostParams keep;
  keep.remove_orphans = false;
  const auto k = cc::postprocess(p, f, keep);
  CHECK(k.kept.size() == 5);
  CHECK(k.faces == std::vector<cc::Face>{{1, 2, 3}});
}

TEST_CASE("rules run in the thesis order and keep face orientation") {
  // A fan of 4 triangles around vertex 0; one rim vertex is low, one triangle is huge.
  std::vector<V3> p{{0, 0, 1}, {0.1, 0, 1}, {0, 0.1, 1}, {-0.1, 0, 0.1}, {0, -0.6, 1}};
  std::vector<cc::Face> f{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  const auto r = cc::postprocess(p, f, cc::PostParams{});
  CHECK(r.stats.low_vertices == 1);
  CHECK(r.stats.partial_facets == 2);  // the two facets at vertex 3 are gone before rule 3
  CHECK(r.stats.large_facets == 0);
  CHECK(r.stats.sliver_facets == 1);    // {0, 4, 1}: edges 0.6 / 0.1
  CHECK(r.stats.orphan_vertices == 1);  // vertex 4
  CHECK(r.kept == std::vector<std::size_t>{0, 1, 2});
  CHECK(r.faces == std::vector<cc::Face>{{0, 1, 2}});
}
