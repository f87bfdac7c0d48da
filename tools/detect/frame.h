// detect's local frame (step 1 of detect.h): the tile's bounds, an integer-metre origin and
// every point's coordinates minus it (float64), so PCL's float32 sees small numbers only.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"

namespace canopy::detect {

// The tile in its local frame: bounds (tile coordinates), the integer-metre origin, and every
// point's coordinates minus the origin.
struct LocalFrame {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<double> x, y, z;
};

// The origin is the floor of the bounding-box centre in x, y and of the lowest z. Throws
// common::DataError naming `name` for non-finite coordinates and for float32 coordinates at
// magnitudes where float32 is not exact (2^17 m and beyond).
LocalFrame local_frame(const formats::PointCloud& tile, const std::string& name);

}  // namespace canopy::detect
