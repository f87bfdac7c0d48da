#include "canopy/common/stats.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace canopy::common {

Interval wilson(int k, int n, double z) {
  if (n < 0 || k < 0 || k > n) {
    throw std::invalid_argument("wilson: " + std::to_string(k) + " of " + std::to_string(n) +
                                " is no proportion");
  }
  if (n == 0) return {0, 1};
  return wilson_effective(static_cast<double>(k) / n, n, z);
}

Interval wilson_effective(double p, double n, double z) {
  if (!(p >= 0 && p <= 1))
    throw std::invalid_argument("wilson_effective: " + std::to_string(p) + " is no proportion");
  if (!(n > 0)) return {0, 1};
  const double z2 = z * z;
  const double centre = (p + z2 / (2.0 * n)) / (1 + z2 / n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2 / (4.0 * n * n)) / (1 + z2 / n);
  // (at p = 0 and p = 1 the bounds are 0 and 1 exactly; rounding must not move them past)
  return {p == 0 ? 0.0 : std::max(0.0, centre - half), p == 1 ? 1.0 : std::min(1.0, centre + half)};
}

double sorted_quantile(const std::vector<double>& v, double q) {
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

namespace {

// P(X <= k) for X ~ Poisson(mean), summed in log space.
double poisson_cdf(int k, double mean) {
  if (mean <= 0) return 1;
  double sum = 0;
  for (int i = 0; i <= k; ++i) sum += std::exp(-mean + i * std::log(mean) - std::lgamma(i + 1.0));
  return std::min(1.0, sum);
}

// The mean at which P(X <= k) = target (P falls as the mean grows).
double mean_where_cdf(int k, double target) {
  double lo = 0, hi = std::max(10.0, 4.0 * k + 10);
  while (poisson_cdf(k, hi) > target) hi *= 2;
  for (int it = 0; it < 200 && hi - lo > 1e-9 * std::max(1.0, hi); ++it) {
    const double mid = 0.5 * (lo + hi);
    (poisson_cdf(k, mid) > target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

Interval poisson_exact(int k, double confidence) {
  if (k < 0) throw std::invalid_argument("poisson_exact: a count of " + std::to_string(k));
  if (!(confidence > 0 && confidence < 1))
    throw std::invalid_argument("poisson_exact: confidence out of (0, 1)");
  const double tail = (1 - confidence) / 2;
  // lo: P(X >= k) = tail, i.e. P(X <= k - 1) = 1 - tail; hi: P(X <= k) = tail.
  return {k == 0 ? 0.0 : mean_where_cdf(k - 1, 1 - tail), mean_where_cdf(k, tail)};
}

std::optional<Interval> cluster_bootstrap(const std::vector<ClusterSum>& clusters, int resamples,
                                          std::uint64_t seed, double confidence) {
  if (resamples < 1) throw std::invalid_argument("cluster_bootstrap: no resamples");
  if (!(confidence > 0 && confidence < 1))
    throw std::invalid_argument("cluster_bootstrap: confidence out of (0, 1)");
  const std::size_t n = clusters.size();
  if (n < 2) return std::nullopt;
  std::mt19937_64 rng(seed);
  std::vector<double> ratios;
  ratios.reserve(static_cast<std::size_t>(resamples));
  for (int b = 0; b < resamples; ++b) {
    double num = 0, den = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const ClusterSum& c = clusters[rng() % n];
      num += c.num;
      den += c.den;
    }
    if (den > 0) ratios.push_back(num / den);
  }
  if (ratios.empty()) return std::nullopt;
  std::sort(ratios.begin(), ratios.end());
  const double tail = (1 - confidence) / 2;
  return Interval{sorted_quantile(ratios, tail), sorted_quantile(ratios, 1 - tail)};
}

}  // namespace canopy::common
