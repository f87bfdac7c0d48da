// Mathematical constants shared by every stage (one π for the whole toolchain).
#pragma once

namespace canopy::common {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegree = kPi / 180;  // one degree in radians

}  // namespace canopy::common
