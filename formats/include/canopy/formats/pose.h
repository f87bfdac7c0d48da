// A rigid pose as canopy's documents write it (the verdict's poses, classify's answer): the
// row-major rotation and the translation of p_to = rotation * p_from + translation.
#pragma once

#include <array>

namespace canopy::formats {

struct Pose {
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
  std::array<double, 3> translation{};
};

// Heading, pitch, roll in degrees of a rotation (R = Rz(heading) Ry(pitch) Rx(roll)).
std::array<double, 3> euler_degrees(const Pose& pose);

}  // namespace canopy::formats
