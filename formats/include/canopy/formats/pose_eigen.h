// The documents' poses (formats::Pose: row-major rotation + translation; a row-major 4 x 4 array)
// <-> Eigen: the one conversion verify (its ICP poses, a match result's given poses) and baseline
// (its registration matrices) write and read with.
#pragma once

#include <array>

#include <Eigen/Geometry>

#include "canopy/formats/pose.h"

namespace canopy::formats {

// The rigid part of a 4 x 4 matrix (upper-left 3 x 3 and last column; the last row is ignored).
inline Pose to_pose(const Eigen::Matrix4d& m) {
  Pose p;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) p.rotation[3 * r + c] = m(r, c);
    p.translation[r] = m(r, 3);
  }
  return p;
}

inline Pose to_pose(const Eigen::Isometry3d& t) { return to_pose(t.matrix()); }

inline Eigen::Isometry3d to_isometry(const Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) t.linear()(r, c) = p.rotation[3 * r + c];
    t.translation()(r) = p.translation[r];
  }
  return t;
}

// A 4 x 4 matrix as the documents' row-major arrays (a baseline ranking's and a match result's
// "pose") and back.
inline std::array<double, 16> to_row_major(const Eigen::Matrix4d& m) {
  std::array<double, 16> a{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) a[static_cast<std::size_t>(4 * r + c)] = m(r, c);
  }
  return a;
}

inline Eigen::Isometry3d to_isometry(const std::array<double, 16>& a) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = a[static_cast<std::size_t>(4 * r + c)];
  }
  return Eigen::Isometry3d(m);
}

}  // namespace canopy::formats
