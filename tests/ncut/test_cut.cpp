// Normalized-cut core on hand-checked graphs.
#include <catch2/catch.hpp>

#include <cmath>
#include <set>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/common/rng.h"
#include "ncut/cut.h"
#include "ncut/graph.h"

using namespace canopy::ncut;

namespace {

void clique(std::vector<Edge>* e, int first, int size, double w) {
  for (int a = first; a < first + size; ++a) {
    for (int b = a + 1; b < first + size; ++b) e->push_back({a, b, w});
  }
}

// Two partitions are the same up to renaming.
bool same_partition(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t j = i + 1; j < a.size(); ++j) {
      if ((a[i] == a[j]) != (b[i] == b[j])) return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("graph: rows sorted, degrees, duplicate edges rejected, components ordered") {
  Graph g(5, {{3, 1, 2.0}, {1, 0, 1.0}, {4, 2, 0.5}, {0, 3, 0.0}});
  CHECK(g.edge_count() == 3);  // the zero-weight edge is dropped
  CHECK(g.degree(1) == 3.0);
  CHECK(*g.nbr_begin(1) == 0);
  const auto comps = g.components();
  REQUIRE(comps.size() == 2);
  CHECK(comps[0] == std::vector<int>{0, 1, 3});
  CHECK(comps[1] == std::vector<int>{2, 4});
  CHECK_THROWS(Graph(3, {{0, 1, 1.0}, {1, 0, 1.0}}));
  CHECK_THROWS(Graph(3, {{0, 0, 1.0}}));
}

TEST_CASE("block-diagonal graph splits exactly along its blocks") {
  // Three dense blocks with unequal sizes and no edge between them.
  std::vector<Edge> e;
  clique(&e, 0, 7, 1.0);
  clique(&e, 7, 12, 0.8);
  clique(&e, 19, 5, 1.3);
  const Graph g(24, e);
  CutStats st;
  const auto label = recursive_ncut(g, CutParams{}, &st);
  std::vector<int> want(24);
  for (int v = 0; v < 24; ++v) want[v] = v < 7 ? 0 : v < 19 ? 1 : 2;
  CHECK(label == want);
  CHECK(st.components == 3);
  CHECK(st.splits == 0);
  CHECK(st.rejected == 3);  // each clique is tried and has no cut below 0.1
}

TEST_CASE("two cliques joined by one weak edge: one split with the expected Ncut") {
  const int k = 10;
  const double eps = 0.05;
  std::vector<Edge> e;
  clique(&e, 0, k, 1.0);
  clique(&e, k, k, 1.0);
  e.push_back({3, k + 6, eps});
  const Graph g(2 * k, e);
  // vol(A) = vol(B) = k (k - 1) + eps, cut = eps.
  const double expected = 2 * eps / (k * (k - 1) + eps);

  for (Solver s : {Solver::kDense, Solver::kLanczos, Solver::kShiftInvert}) {
    CutParams p;
    p.solver = s;
    CutStats st;
    const EigenResult ev = second_eigenvector(g, p, &st);
    Eigen::VectorXd y(2 * k);
    for (int v = 0; v < 2 * k; ++v) y[v] = ev.z[v] / std::sqrt(g.degree(v));
    const SweepCut cut = best_sweep_cut(g, y, 1);
    REQUIRE(cut.found);
    CHECK(cut.ncut == Approx(expected).epsilon(1e-12));
    for (int v = 0; v < 2 * k; ++v) CHECK(cut.in_a[v] == cut.in_a[v < k ? 0 : k]);
    CHECK(cut.in_a[0] != cut.in_a[k]);

    const auto label = recursive_ncut(g, p, &st);
    std::vector<int> want(2 * k);
    for (int v = 0; v < 2 * k; ++v) want[v] = v < k ? 0 : 1;
    CHECK(label == want);
    CHECK(st.splits == 1);
  }
  // The same two cliques with a strong bridge stay together at max_ncut = 0.1.
  std::vector<Edge> e2;
  clique(&e2, 0, 4, 1.0);
  clique(&e2, 4, 4, 1.0);
  for (int a = 0; a < 4; ++a) e2.push_back({a, 4 + a, 1.0});
  const auto label2 = recursive_ncut(Graph(8, e2), CutParams{}, nullptr);
  CHECK(std::set<int>(label2.begin(), label2.end()).size() == 1);
}

TEST_CASE("isolated vertices and several components: no NaN, each its own segment") {
  std::vector<Edge> e;
  clique(&e, 1, 4, 1.0);      // vertices 1..4
  e.push_back({6, 7, 1e-9});  // a weak pair
  clique(&e, 9, 3, 2.0);      // 9..11; 0, 5, 8 isolated
  const Graph g(12, e);
  for (int v : {0, 5, 8}) CHECK(g.degree(v) == 0);
  CutStats st;
  const auto label = recursive_ncut(g, CutParams{}, &st);
  CHECK(label == std::vector<int>{0, 1, 1, 1, 1, 2, 3, 3, 4, 5, 5, 5});
  CHECK(st.components == 6);
  CHECK(std::isfinite(st.max_residual));
}

TEST_CASE("sweep equals brute force over all thresholds on random graphs") {
  canopy::common::Rng rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 6 + static_cast<int>(rng.below(6));
    std::vector<Edge> e;
    for (int a = 0; a < n; ++a) {
      e.push_back({a, (a + 1) % n, 0.1 + rng.uniform()});  // a ring keeps it connected
      for (int b = a + 2; b < n; ++b) {
        if (!(a == 0 && b == n - 1) && rng.uniform() < 0.3) e.push_back({a, b, rng.uniform()});
      }
    }
    const Graph g(n, e);
    Eigen::VectorXd y(n);
    for (int v = 0; v < n; ++v) y[v] = std::floor(rng.uniform() * 4);  // with ties
    const SweepCut cut = best_sweep_cut(g, y, 1);
    // Brute force: every threshold t between distinct values, A = {y <= t}.
    std::set<double> values(y.data(), y.data() + n);
    double best = INFINITY;
    for (double t : values) {
      std::vector<char> in_a(n);
      int size_a = 0;
      for (int v = 0; v < n; ++v) size_a += in_a[v] = y[v] <= t;
      if (size_a == n) continue;
      best = std::min(best, ncut_value(g, in_a));
    }
    if (values.size() < 2) {
      CHECK_FALSE(cut.found);
    } else {
      REQUIRE(cut.found);
      CHECK(cut.ncut == Approx(best).epsilon(1e-12));
      for (int v = 0; v < n; ++v) {  // ties stay together
        for (int u = 0; u < n; ++u) {
          if (y[u] == y[v]) CHECK(cut.in_a[u] == cut.in_a[v]);
        }
      }
    }
  }
}

TEST_CASE("solvers agree on the second eigenpair of a grid with a weak crease") {
  // 30 x 20 grid, 4-neighbour weights, the column between x = 14 and 15 weakened.
  const int nx = 30, ny = 20;
  canopy::common::Rng rng(5);
  std::vector<Edge> e;
  auto id = [&](int x, int y) { return x * ny + y; };
  for (int x = 0; x < nx; ++x) {
    for (int y = 0; y < ny; ++y) {
      if (x + 1 < nx) e.push_back({id(x, y), id(x + 1, y), (x == 14 ? 0.02 : 1.0) * rng.uniform(0.9, 1.1)});
      if (y + 1 < ny) e.push_back({id(x, y), id(x, y + 1), rng.uniform(0.9, 1.1)});
    }
  }
  const Graph g(nx * ny, e);
  std::vector<EigenResult> r;
  std::vector<std::vector<int>> labels;
  for (Solver s : {Solver::kDense, Solver::kLanczos, Solver::kShiftInvert}) {
    CutParams p;
    p.solver = s;
    p.dense_max = 100000;
    r.push_back(second_eigenvector(g, p, nullptr));
    CHECK(r.back().residual < 1e-8);
    labels.push_back(recursive_ncut(g, p, nullptr));
  }
  for (std::size_t k = 1; k < r.size(); ++k) {
    CHECK(r[k].mu == Approx(r[0].mu).margin(1e-9));
    CHECK(std::abs(r[k].z.dot(r[0].z)) == Approx(1.0).margin(1e-6));
    CHECK(same_partition(labels[k], labels[0]));
  }
  // The crease is the first cut.
  const auto& l = labels[0];
  CHECK(l[id(0, 0)] != l[id(nx - 1, 0)]);
}

TEST_CASE("a failing eigensolve falls back, and fails loudly when nothing converges") {
  // A long path graph: tiny spectral gap, slow for regular Lanczos.
  auto path = [](int n) {
    std::vector<Edge> e;
    for (int a = 0; a + 1 < n; ++a) e.push_back({a, a + 1, 1.0});
    return Graph(n, e);
  };
  CutParams p;
  p.solver = Solver::kLanczos;
  p.max_restarts = 1;
  p.ncv = 3;
  CutStats st;
  const EigenResult r = second_eigenvector(path(400), p, &st);
  CHECK(st.fallbacks == 1);
  CHECK(r.residual < 1e-8);

  p.fallback = false;
  CHECK_THROWS_AS(second_eigenvector(path(400), p, nullptr), canopy::common::Error);
  CHECK_THROWS_AS(recursive_ncut(path(400), p, nullptr), canopy::common::Error);
}
