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

// "" when `number` (a whole decimal_prefix) is a usable double, else the message: beyond
// DBL_MAX ("1e999"), nonzero but below DBL_MIN (1e-400 would silently become 0, 1e-310 a
// subnormal), or a negative zero ("-0", "-0.0e5": a minus sign that changes nothing but
// printing and 1/x).
std::string decimal_problem(const std::string& number);

// A decimal real number (the grammar of decimal_prefix, the whole text, decimal_problem ""),
// for options a tool parses itself ("auto" or a number, lists): UsageError naming `what`
// (e.g. "--support") otherwise. No hex ("0x10", "0x1p0"), "inf", "nan", spaces or suffixes.
double parse_decimal(const std::string& text, const std::string& what);

// Returns metres.
double parse_length(const std::string& text);
// Returns radians.
double parse_angle(const std::string& text);
// Shortest text that parses back to the same value: "0.128m" style for lengths, "22.5deg" for angles.
std::string format_length(double metres);
std::string format_angle(double radians);

}  // namespace canopy::common
