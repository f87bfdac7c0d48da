// Small geometry shared by stages (header-only).
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <limits>

namespace canopy::common {

// The extent of planar points along two directions: [umin, umax] along u, [vmin, vmax] along v
// (the projections q · u and q · v). Empty input: +inf minima, -inf maxima.
struct Extent2 {
  double umin = std::numeric_limits<double>::infinity(), umax = -std::numeric_limits<double>::infinity();
  double vmin = std::numeric_limits<double>::infinity(), vmax = -std::numeric_limits<double>::infinity();
};

// `points`: any range of Eigen::Vector2d.
template <class Points>
Extent2 extent_along(const Points& points, const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
  Extent2 e;
  for (const Eigen::Vector2d& q : points) {
    const double a = q.dot(u), b = q.dot(v);
    e.umin = std::min(e.umin, a);
    e.umax = std::max(e.umax, a);
    e.vmin = std::min(e.vmin, b);
    e.vmax = std::max(e.vmax, b);
  }
  return e;
}

}  // namespace canopy::common
