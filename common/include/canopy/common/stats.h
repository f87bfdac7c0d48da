// Confidence intervals of the rates and counts the experiment reports (95% unless told): one
// implementation for every report section and tool.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace canopy::common {

struct Interval {
  double lo = 0, hi = 0;
};

// The two-sided 95% normal quantile.
inline constexpr double kZ95 = 1.959963984540054;

// Wilson score interval of a proportion of k successes in n trials (0 <= k <= n; n = 0 gives
// [0, 1]: nothing is known): (p + z²/2n ± z √(p(1−p)/n + z²/4n²)) / (1 + z²/n), p = k/n.
Interval wilson(int k, int n, double z = kZ95);

// The same formula for a proportion p in [0, 1] observed on an effective sample of n_eff > 0
// units (a count of correlated trials divided by its design effect, e.g. vehicle-runs over
// noise levels that reuse one render: n_eff = runs x renders / tiles). n_eff <= 0: [0, 1].
Interval wilson_effective(double p, double n_eff, double z = kZ95);

// Exact (Garwood 1936) central interval of a Poisson mean from one observed count k >= 0 at
// `confidence` (0 < confidence < 1): lo = ½ χ²(α/2; 2k) (0 when k = 0), hi = ½ χ²(1 − α/2;
// 2k + 2), α = 1 − confidence; found as the means at which P(X >= k) and P(X <= k) equal α/2
// (bisection on the Poisson distribution, to 1e-9 relative). Divide by an area or a time for
// the interval of a rate (e.g. false alarms per hectare).
Interval poisson_exact(int k, double confidence = 0.95);

// Quantile q in [0, 1] of `sorted` (ascending, not empty): linear interpolation between order
// statistics, the "type 7" definition (the median of an even count is the mean of the middle
// two). score's and report's percentiles, and the bootstrap's bounds.
double sorted_quantile(const std::vector<double>& sorted, double q);

// One cluster's share of a ratio of sums: what it adds to the numerator and the denominator
// (a tile's true positives and true vehicles, its false alarms and hectares, ...).
struct ClusterSum {
  double num = 0, den = 0;
};

// Percentile bootstrap interval of sum(num) / sum(den) when the clusters, not their members,
// are the independent units (vehicles that share a tile, tiles that share a render):
// `resamples` draws of clusters.size() clusters with replacement; the ratio of each draw whose
// sum(den) > 0; the (1 - confidence)/2 and (1 + confidence)/2 percentiles of those ratios
// (linear interpolation, "type 7"). Deterministic: std::mt19937_64(seed), the k-th cluster of a
// draw = the generator's next value modulo clusters.size(). nullopt when there are fewer than 2
// clusters or no draw has sum(den) > 0 (one cluster tells nothing of the spread between them).
std::optional<Interval> cluster_bootstrap(const std::vector<ClusterSum>& clusters, int resamples = 2000,
                                          std::uint64_t seed = 20021, double confidence = 0.95);

}  // namespace canopy::common
