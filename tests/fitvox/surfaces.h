// Analytic surface patches sampled in code for the fitvox tests.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <vector>

#include "canopy/common/rng.h"

namespace fitvox_test {

using Eigen::Vector3d;

inline Vector3d random_unit(canopy::common::Rng& rng) {
  Vector3d d(rng.normal(), rng.normal(), rng.normal());
  return d.normalized();
}

// Orthonormal right-handed frame (t1, t2, n) with n given.
inline void frame_for(const Vector3d& n, Vector3d* t1, Vector3d* t2) {
  const Vector3d a = std::abs(n.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
  *t1 = n.cross(a).normalized();
  *t2 = n.cross(*t1);
}

inline void add_noise(std::vector<Vector3d>* pts, double sigma, canopy::common::Rng& rng) {
  for (Vector3d& p : *pts) p += sigma * Vector3d(rng.normal(), rng.normal(), rng.normal());
}

// Index of the point nearest q.
inline std::size_t nearest(const std::vector<Vector3d>& pts, const Vector3d& q) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    if ((pts[i] - q).squaredNorm() < (pts[best] - q).squaredNorm()) best = i;
  }
  return best;
}

// k points on the plane through c with unit normal n, in a square of half-width hw.
inline std::vector<Vector3d> plane_patch(const Vector3d& c, const Vector3d& n, double hw, int k,
                                         canopy::common::Rng& rng) {
  Vector3d t1, t2;
  frame_for(n, &t1, &t2);
  std::vector<Vector3d> pts;
  for (int i = 0; i < k; ++i) pts.push_back(c + rng.uniform(-hw, hw) * t1 + rng.uniform(-hw, hw) * t2);
  return pts;
}

// k points on the sphere (centre, R) around the direction d, patch of half-width ~hw (arc).
inline std::vector<Vector3d> sphere_patch(const Vector3d& centre, double r, const Vector3d& d,
                                          double hw, int k, canopy::common::Rng& rng) {
  Vector3d t1, t2;
  frame_for(d, &t1, &t2);
  std::vector<Vector3d> pts;
  for (int i = 0; i < k; ++i) {
    const double a = rng.uniform(-hw, hw) / r, b = rng.uniform(-hw, hw) / r;
    pts.push_back(centre + r * (d + std::tan(a) * t1 + std::tan(b) * t2).normalized());
  }
  return pts;
}

// k points on the cylinder (point on axis c, unit axis ax, radius R) around the radial
// direction d (perpendicular to ax): axial half-length hw, arc half-length hw.
inline std::vector<Vector3d> cylinder_patch(const Vector3d& c, const Vector3d& ax, double r,
                                            const Vector3d& d, double hw, int k,
                                            canopy::common::Rng& rng) {
  const Vector3d e2 = ax.cross(d);
  std::vector<Vector3d> pts;
  for (int i = 0; i < k; ++i) {
    const double t = rng.uniform(-hw, hw), th = rng.uniform(-hw, hw) / r;
    pts.push_back(c + t * ax + r * (std::cos(th) * d + std::sin(th) * e2));
  }
  return pts;
}

}  // namespace fitvox_test
