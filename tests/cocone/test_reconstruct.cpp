// Cocone on analytic shapes with known answers (shared spec ALGORITHMS.md §G).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/common/rng.h"
#include "cocone/cocone.h"
#include "mesh_checks.h"

namespace cc = canopy::cocone;
using cocone_test::topology;
using V3 = Eigen::Vector3d;

namespace {

std::vector<V3> sphere(std::size_t n, std::uint64_t seed) {
  canopy::common::Rng rng(seed);
  std::vector<V3> p(n);
  for (auto& x : p) {
    V3 g(rng.normal(), rng.normal(), rng.normal());
    x = g.normalized();
  }
  return p;
}

// Area-uniform torus, major radius R = 1, minor radius r = 0.35, around the z axis.
std::vector<V3> torus(std::size_t n, std::uint64_t seed) {
  canopy::common::Rng rng(seed);
  const double R = 1.0, r = 0.35;
  std::vector<V3> p;
  while (p.size() < n) {
    const double u = rng.uniform(0, 2 * canopy::common::kPi), v = rng.uniform(0, 2 * canopy::common::kPi);
    if (rng.uniform() * (R + r) > R + r * std::cos(v)) continue;
    p.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
  }
  return p;
}

// Regular m x m grid over [-1, 1]^2 lifted onto a gentle saddle-free bump.
std::vector<V3> height_field(int m) {
  std::vector<V3> p;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const double x = -1 + 2.0 * i / (m - 1), y = -1 + 2.0 * j / (m - 1);
      p.emplace_back(x, y, 0.3 * std::exp(-(x * x + y * y)));
    }
  return p;
}

std::set<std::array<int, 3>> triangle_set(const std::vector<cc::Face>& faces) {
  std::set<std::array<int, 3>> s;
  for (const auto& f : faces) {
    std::array<int, 3> t{f[0], f[1], f[2]};
    std::sort(t.begin(), t.end());
    s.insert(t);
  }
  return s;
}

struct Quiet {
  Quiet() { canopy::common::log::set_level(canopy::common::log::Level::kQuiet); }
};
const Quiet quiet;

}  // namespace

TEST_CASE("uniform sphere: 2N-4 triangles, closed, chi = 2, outward") {
  const std::size_t n = 10000;
  const auto p = sphere(n, 1);
  const auto s = cc::reconstruct(p, {}, cc::CoconeParams{});
  CHECK(s.faces.size() == 2 * n - 4);
  const auto t = topology(s.faces);
  CHECK(t.vertices == n);
  CHECK(t.boundary_edges == 0);
  CHECK(t.nonmanifold_edges == 0);
  CHECK(t.inconsistent_edges == 0);
  CHECK(t.euler() == 2);
  CHECK(cocone_test::signed_volume(p, s.faces) > 0);
}

TEST_CASE("plain Cocone (no boundary detection) also closes the sphere") {
  const std::size_t n = 4000;
  const auto p = sphere(n, 2);
  cc::CoconeParams prm;
  prm.boundary_detection = false;
  const auto s = cc::reconstruct(p, {}, prm);
  CHECK(s.faces.size() == 2 * n - 4);
  CHECK(topology(s.faces).euler() == 2);
}

TEST_CASE("uniform torus: 2N triangles, closed, chi = 0") {
  const std::size_t n = 10000;
  const auto p = torus(n, 3);
  const auto s = cc::reconstruct(p, {}, cc::CoconeParams{});
  CHECK(s.faces.size() == 2 * n);
  const auto t = topology(s.faces);
  CHECK(t.vertices == n);
  CHECK(t.boundary_edges == 0);
  CHECK(t.nonmanifold_edges == 0);
  CHECK(t.inconsistent_edges == 0);
  CHECK(t.euler() == 0);
}

TEST_CASE("open height field on a regular grid: one boundary loop, manifold edges") {
  const int m = 40;
  const auto p = height_field(m);
  const auto s = cc::reconstruct(p, {}, cc::CoconeParams{});
  const auto t = topology(s.faces);
  CHECK(t.nonmanifold_edges == 0);
  CHECK(t.inconsistent_edges == 0);
  CHECK(t.boundary_loops == 1);
  // Dey-Giesen: the 4(m-1) border samples are the boundary, the interior survives pruning.
  const std::size_t border = 4 * (m - 1);
  CHECK(s.stats.flat + border >= p.size() - border / 4);
  CHECK(s.stats.flat <= p.size() - border / 2);
  // A triangulated square grid has 2(m-1)^2 triangles; nearly all of it must come back.
  CHECK(s.faces.size() >= static_cast<std::size_t>(0.95 * 2 * (m - 1) * (m - 1)));
  CHECK(s.faces.size() <= static_cast<std::size_t>(2 * (m - 1) * (m - 1)));
}

TEST_CASE("open surface faces follow the reference normals") {
  const auto p = height_field(20);
  std::vector<V3> up(p.size(), V3::UnitZ()), down(p.size(), -V3::UnitZ());
  for (const auto& normals : {up, down}) {
    const auto s = cc::reconstruct(p, normals, cc::CoconeParams{});
    REQUIRE(!s.faces.empty());
    for (const auto& f : s.faces) {
      const V3 n = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
      CHECK(n.dot(normals[0]) > 0);
    }
  }
}

TEST_CASE("noisy sphere does not collapse under pruning") {
  const std::size_t n = 10000;
  auto p = sphere(n, 4);
  const double spacing = std::sqrt(4 * canopy::common::kPi / n);
  canopy::common::Rng rng(5);
  for (auto& x : p) x *= 1 + 0.05 * spacing * rng.normal();
  const auto s = cc::reconstruct(p, {}, cc::CoconeParams{});
  const auto t = topology(s.faces);
  CHECK(t.nonmanifold_edges == 0);
  CHECK(t.inconsistent_edges == 0);
  CHECK(s.faces.size() >= (2 * n - 4) * 9 / 10);
}

TEST_CASE("same samples in another order give the same triangles") {
  const std::size_t n = 3000;
  const auto p = torus(n, 6);
  std::vector<std::size_t> perm(n);
  for (std::size_t i = 0; i < n; ++i) perm[i] = (i * 7919) % n;  // 7919 is prime, n = 3000
  std::vector<V3> q(n);
  for (std::size_t i = 0; i < n; ++i) q[i] = p[perm[i]];
  const auto a = cc::reconstruct(p, {}, cc::CoconeParams{});
  auto b = cc::reconstruct(q, {}, cc::CoconeParams{});
  for (auto& f : b.faces)
    for (auto& v : f) v = static_cast<int>(perm[v]);
  CHECK(triangle_set(a.faces) == triangle_set(b.faces));
  const auto again = cc::reconstruct(p, {}, cc::CoconeParams{});
  CHECK(again.faces == a.faces);
}

TEST_CASE("duplicate rows are merged: the first occurrence carries the triangles") {
  const std::size_t n = 2000;
  auto p = sphere(n, 7);
  const auto base = cc::reconstruct(p, {}, cc::CoconeParams{});
  p.push_back(p[10]);
  p.push_back(p[20]);
  p.push_back(p[10]);
  const auto s = cc::reconstruct(p, {}, cc::CoconeParams{});
  CHECK(s.stats.duplicates == 3);
  CHECK(triangle_set(s.faces) == triangle_set(base.faces));
}

TEST_CASE("degenerate inputs give a clear error") {
  using Catch::Matchers::Contains;
  const cc::CoconeParams prm;
  std::vector<V3> three{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  CHECK_THROWS_WITH(cc::reconstruct(three, {}, prm), Contains("at least 4 distinct"));
  std::vector<V3> dups{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 0}};
  CHECK_THROWS_WITH(cc::reconstruct(dups, {}, prm), Contains("at least 4 distinct"));
  std::vector<V3> plane;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) plane.emplace_back(i * 0.1, j * 0.1 + 0.01 * i, 0.5);
  CHECK_THROWS_WITH(cc::reconstruct(plane, {}, prm), Contains("coplanar"));
  std::vector<V3> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(i, 2 * i, 3 * i);
  CHECK_THROWS_WITH(cc::reconstruct(line, {}, prm), Contains("collinear"));
  std::vector<V3> nan{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::nan("")}};
  CHECK_THROWS_WITH(cc::reconstruct(nan, {}, prm), Contains("non-finite"));
  CHECK_THROWS_AS(cc::reconstruct(three, {}, prm), canopy::common::Error);
}

TEST_CASE("a tetrahedron gives a defined, manifold result") {
  std::vector<V3> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const auto s = cc::reconstruct(p, {}, cc::CoconeParams{});
  const auto t = topology(s.faces);
  CHECK(s.faces.size() <= 4);
  CHECK(t.nonmanifold_edges == 0);
  CHECK(t.inconsistent_edges == 0);
}
