// Confidence intervals (common/stats.h) against published values: Wilson score intervals as
// tabulated by Newcombe (1998, Table I) and recomputed by hand from the formula, and the exact
// (Garwood) Poisson intervals of the standard tables (½ χ² quantiles).
#include <catch2/catch.hpp>

#include <stdexcept>

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
