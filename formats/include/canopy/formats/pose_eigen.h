// The documents' poses (formats::Pose: row-major rotation + translation) <-> Eigen: the one
// conversion verify (its ICP poses) and baseline (its registration matrices) write with.
#pragma once

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

}  // namespace canopy::formats
