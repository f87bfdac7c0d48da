// Command-line quantities with units. Lengths: "128mm", "12.8cm", "0.128m", bare = metres.
// Angles: "10deg", "0.17rad", bare = degrees. Both throw UsageError on malformed text.
#pragma once

#include <string>

namespace canopy::common {

// Returns metres.
double parse_length(const std::string& text);
// Returns radians.
double parse_angle(const std::string& text);
// Shortest text that parses back to the same value: "0.128m" style for lengths, "22.5deg" for angles.
std::string format_length(double metres);
std::string format_angle(double radians);

}  // namespace canopy::common
