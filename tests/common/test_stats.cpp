// Confidence intervals (common/stats.h) against published values: Wilson score intervals as
// tabulated by Newcombe (1998, Table I) and recomputed by hand from the formula, and the exact
// (Garwood) Poisson intervals of the standard tables (½ χ² quantiles).
#include <catch2/catch.hpp>

#include <stdexcept>
#include <vector>

#include "canopy/common/stats.h"

using canopy::common::poisson_exact;
using canopy::common::wilson;

TEST_CASE("wilson: known intervals, the edges, no proportion refused") {
  // 8/10: p = 0.8, centre 0.71674, half-width 0.22657.
  const auto a = wilson(8, 10);
  CHECK(a.lo == Approx(0.4902).margin(1e-4));
  CHECK(a.hi == Approx(0.9433).margin(1e-4));
  // Newcombe 1998, Table I: 81/263 -> 0.2553-0.3662; 15/148 -> 0.0624-0.1605.
  CHECK(wilson(81, 263).lo == Approx(0.2553).margin(1e-4));
  CHECK(wilson(81, 263).hi == Approx(0.3662).margin(1e-4));
  CHECK(wilson(15, 148).lo == Approx(0.0624).margin(1e-4));
  CHECK(wilson(15, 148).hi == Approx(0.1605).margin(1e-4));
  // 0/10 and 10/10: one bound exact, the other 1 - 0.7225 = 0.2775 away.
  CHECK(wilson(0, 10).lo == 0);
  CHECK(wilson(0, 10).hi == Approx(0.2775).margin(1e-4));
  CHECK(wilson(10, 10).hi == 1);
  CHECK(wilson(10, 10).lo == Approx(0.7225).margin(1e-4));
  // Nothing observed: nothing known.
  CHECK(wilson(0, 0).lo == 0);
  CHECK(wilson(0, 0).hi == 1);
  CHECK_THROWS_AS(wilson(3, 2), std::invalid_argument);
  CHECK_THROWS_AS(wilson(-1, 2), std::invalid_argument);
}

TEST_CASE("poisson_exact: Garwood's intervals of the tables") {
  struct Row {
    int k;
    double lo, hi;
  };
  for (const Row& r : {Row{0, 0, 3.6889}, Row{1, 0.0253, 5.5716}, Row{3, 0.6186, 8.7673},
                       Row{8, 3.4538, 15.7632}, Row{20, 12.2165, 30.8884}}) {
    INFO("k = " << r.k);
    const auto i = poisson_exact(r.k);
    CHECK(i.lo == Approx(r.lo).margin(2e-4));
    CHECK(i.hi == Approx(r.hi).margin(2e-4));
  }
  // 90%: k = 0 -> -ln 0.05 = 2.9957.
  CHECK(poisson_exact(0, 0.90).hi == Approx(2.9957).margin(2e-4));
  CHECK_THROWS_AS(poisson_exact(-1), std::invalid_argument);
  CHECK_THROWS_AS(poisson_exact(2, 1.0), std::invalid_argument);
}

TEST_CASE("wilson_effective: Wilson's interval at a real-valued sample size") {
  using canopy::common::wilson_effective;
  // Whole counts give Wilson's interval.
  CHECK(wilson_effective(0.8, 10).lo == Approx(wilson(8, 10).lo));
  CHECK(wilson_effective(0.8, 10).hi == Approx(wilson(8, 10).hi));
  CHECK(wilson_effective(81.0 / 263, 263).lo == Approx(0.2553).margin(1e-4));
  // 30 vehicle-runs over 3 noise levels of 10 renders: the interval of 10 units, wider.
  const auto runs = wilson(24, 30), units = wilson_effective(0.8, 10);
  CHECK(units.hi - units.lo > runs.hi - runs.lo);
  CHECK(wilson_effective(1.0, 10).hi == 1);
  CHECK(wilson_effective(0.0, 10).lo == 0);
  CHECK(wilson_effective(0.5, 0).lo == 0);
  CHECK(wilson_effective(0.5, 0).hi == 1);
  CHECK_THROWS_AS(wilson_effective(1.5, 10), std::invalid_argument);
}

TEST_CASE("cluster_bootstrap: known spreads, clusters counted once, deterministic") {
  using canopy::common::cluster_bootstrap;
  using canopy::common::ClusterSum;
  // Nothing to resample.
  CHECK_FALSE(cluster_bootstrap({}).has_value());
  CHECK_FALSE(cluster_bootstrap({{3, 4}}).has_value());
  CHECK_FALSE(cluster_bootstrap({{0, 0}, {0, 0}}).has_value());
  // Every cluster at one ratio: no spread.
  const auto same = cluster_bootstrap({{1, 2}, {2, 4}, {3, 6}});
  REQUIRE(same);
  CHECK(same->lo == Approx(0.5));
  CHECK(same->hi == Approx(0.5));
  // Two clusters, 1/1 and 0/1: a draw of two gives 0, 1/2 or 1 with probabilities 1/4, 1/2,
  // 1/4, so the 2.5th and 97.5th percentiles are 0 and 1.
  const auto two = cluster_bootstrap({{1, 1}, {0, 1}});
  REQUIRE(two);
  CHECK(two->lo == 0);
  CHECK(two->hi == 1);
  // 100 independent units, 30 of them successes: close to the normal interval
  // 0.3 +- 1.96 sqrt(0.21 / 100) = [0.210, 0.390].
  std::vector<ClusterSum> units;
  for (int i = 0; i < 100; ++i) units.push_back({i < 30 ? 1.0 : 0.0, 1.0});
  const auto u = cluster_bootstrap(units);
  REQUIRE(u);
  CHECK(u->lo == Approx(0.210).margin(0.02));
  CHECK(u->hi == Approx(0.390).margin(0.02));
  // The same 100 trials in 10 clusters of 10 that succeed or fail together: 10 units, not 100
  // (normal interval 0.3 +- 1.96 sqrt(0.21 / 10) = [0.016, 0.584]), much wider than Wilson's.
  std::vector<ClusterSum> blocks;
  for (int i = 0; i < 10; ++i) blocks.push_back({i < 3 ? 10.0 : 0.0, 10.0});
  const auto b = cluster_bootstrap(blocks);
  REQUIRE(b);
  CHECK(b->lo == Approx(0.0).margin(0.05));
  CHECK(b->hi == Approx(0.6).margin(0.05));
  CHECK(b->hi - b->lo > 2 * (wilson(30, 100).hi - wilson(30, 100).lo));
  // Same clusters and seed: the same bounds; another seed: the same within resampling noise.
  const auto again = cluster_bootstrap(units);
  CHECK(again->lo == u->lo);
  CHECK(again->hi == u->hi);
  const auto other = cluster_bootstrap(units, 2000, 7);
  CHECK(other->lo == Approx(u->lo).margin(0.02));
  CHECK_THROWS_AS(cluster_bootstrap(units, 0), std::invalid_argument);
}
