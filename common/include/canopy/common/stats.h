// Confidence intervals of the rates and counts the experiment reports (95% unless told): one
// implementation for every report section and tool.
#pragma once

namespace canopy::common {

struct Interval {
  double lo = 0, hi = 0;
};

// The two-sided 95% normal quantile.
inline constexpr double kZ95 = 1.959963984540054;

// Wilson score interval of a proportion of k successes in n trials (0 <= k <= n; n = 0 gives
// [0, 1]: nothing is known): (p + z²/2n ± z √(p(1−p)/n + z²/4n²)) / (1 + z²/n), p = k/n.
Interval wilson(int k, int n, double z = kZ95);

// Exact (Garwood 1936) central interval of a Poisson mean from one observed count k >= 0 at
// `confidence` (0 < confidence < 1): lo = ½ χ²(α/2; 2k) (0 when k = 0), hi = ½ χ²(1 − α/2;
// 2k + 2), α = 1 − confidence; found as the means at which P(X >= k) and P(X <= k) equal α/2
// (bisection on the Poisson distribution, to 1e-9 relative). Divide by an area or a time for
// the interval of a rate (e.g. false alarms per hectare).
Interval poisson_exact(int k, double confidence = 0.95);

}  // namespace canopy::common
