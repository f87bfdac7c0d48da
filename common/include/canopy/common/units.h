// Command-line quantities with units. Lengths: "128mm", "12.8cm", "0.128m", bare = metres.
// Angles: "10deg", "0.17rad", bare = degrees. Both throw UsageError on malformed text.
#pragma once

#include <cstddef>
#include <string>

namespace canopy::common {

// Length of the decimal number at the start of text: [+-]digits[.digits][(e|E)[+-]digits]
// (digits on at least one side of the point); 0 when there is none. Hexadecimal, "inf",
// "nan" and leading spaces are not numbers here.
std::size_t decimal_prefix(const std::string& text);

// Returns metres.
double parse_length(const std::string& text);
// Returns radians.
double parse_angle(const std::string& text);
// Shortest text that parses back to the same value: "0.128m" style for lengths, "22.5deg" for angles.
std::string format_length(double metres);
std::string format_angle(double radians);

}  // namespace canopy::common
