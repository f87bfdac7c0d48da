// Sample clouds shared by the cocone tests.
#pragma once

#include <cmath>

#include "canopy/formats/point_cloud.h"
#include "cocone/cocone.h"

namespace cocone_test {

// Fibonacci sphere (near-uniform spacing) of n samples, radius r, centred at (0, 0, zc):
// fields x y z and the outward unit normal normal_x normal_y normal_z.
inline canopy::formats::PointCloud fibonacci_ball(int n, double r, double zc) {
  canopy::formats::PointCloud c;
  c.resize(static_cast<std::size_t>(n));
  auto& x = c.add("x");
  auto& y = c.add("y");
  auto& z = c.add("z");
  auto& nx = c.add("normal_x");
  auto& ny = c.add("normal_y");
  auto& nz = c.add("normal_z");
  const double golden = canopy::cocone::kPi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double w = 1 - 2 * (i + 0.5) / n, s = std::sqrt(1 - w * w), a = golden * i;
    nx[i] = s * std::cos(a);
    ny[i] = s * std::sin(a);
    nz[i] = w;
    x[i] = r * nx[i];
    y[i] = r * ny[i];
    z[i] = zc + r * nz[i];
  }
  return c;
}

}  // namespace cocone_test
