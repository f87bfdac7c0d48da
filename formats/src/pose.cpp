#include "canopy/formats/pose.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/math.h"

namespace canopy::formats {

std::array<double, 3> euler_degrees(const Pose& p) {
  const auto& R = p.rotation;
  const double deg = 180.0 / common::kPi;
  const double pitch = std::asin(std::max(-1.0, std::min(1.0, -R[6])));
  const double heading = std::atan2(R[3], R[0]);
  const double roll = std::atan2(R[7], R[8]);
  return {heading * deg, pitch * deg, roll * deg};
}

}  // namespace canopy::formats
