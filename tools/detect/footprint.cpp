#include "detect/footprint.h"

#include <algorithm>
#include <limits>

#include "canopy/common/geometry.h"

namespace canopy::detect {
namespace {

using Eigen::Vector2d;

double cross(const Vector2d& o, const Vector2d& a, const Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Andrew's monotone chain; counter-clockwise, no collinear points.
std::vector<Vector2d> convex_hull(std::vector<Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Vector2d& a, const Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<Vector2d> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

}  // namespace

Footprint min_area_rectangle(const std::vector<Vector2d>& points) {
  const std::vector<Vector2d> hull = convex_hull(points);
  Footprint best;
  double best_area = std::numeric_limits<double>::infinity();
  auto consider = [&](const Vector2d& u) {
    const Vector2d v(-u.y(), u.x());
    const auto [umin, umax, vmin, vmax] = common::extent_along(hull, u, v);
    const double area = (umax - umin) * (vmax - vmin);
    if (area < best_area - 1e-12) {
      best_area = area;
      const Vector2d c = 0.5 * (umin + umax) * u + 0.5 * (vmin + vmax) * v;
      best.centre = c;
      if (umax - umin >= vmax - vmin) {
        best.axis = u;
        best.length = umax - umin;
        best.width = vmax - vmin;
      } else {
        best.axis = v;
        best.length = vmax - vmin;
        best.width = umax - umin;
      }
    }
  };
  if (hull.size() < 3) {
    if (hull.size() == 2 && (hull[1] - hull[0]).norm() > 0) {
      consider((hull[1] - hull[0]).normalized());
    } else {
      consider(Vector2d::UnitX());
    }
  } else {
    for (std::size_t e = 0; e < hull.size(); ++e) {
      const Vector2d d = hull[(e + 1) % hull.size()] - hull[e];
      if (d.norm() > 0) consider(d.normalized());
    }
  }
  // Canonical direction: heading in (-pi/2, pi/2].
  if (best.axis.x() < 0 || (best.axis.x() == 0 && best.axis.y() < 0)) best.axis = -best.axis;
  return best;
}

}  // namespace canopy::detect
