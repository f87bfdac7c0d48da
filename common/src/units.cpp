#include "canopy/common/units.h"

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "canopy/common/error.h"
#include "canopy/common/math.h"

namespace canopy::common {
namespace {

// Splits "12.5mm" into 12.5 and "mm". Throws on an empty or non-decimal number part, on a
// space between the number and its unit ("8 mm": a shell word or a config value that held
// two words), and on a number that is not a finite double (see decimal_problem).
double split_number(const std::string& text, std::string* suffix, const char* what) {
  const std::size_t n = decimal_prefix(text);
  if (n == 0) throw UsageError("'" + text + "' is not a " + what);
  *suffix = text.substr(n);
  if (!suffix->empty() && (suffix->front() == ' ' || suffix->front() == '\t')) {
    const std::size_t u = suffix->find_first_not_of(" \t");
    throw UsageError(
        "'" + text + "': no space between the number and its unit" +
        (u == std::string::npos ? std::string() : " (write " + text.substr(0, n) + suffix->substr(u) + ")"));
  }
  const std::string problem = decimal_problem(text.substr(0, n));
  if (!problem.empty()) throw UsageError(problem);
  return std::strtod(text.substr(0, n).c_str(), nullptr);
}

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Shortest plain decimal (no exponent) that reads back exactly; %g only for extreme values.
std::string shortest(double v) {
  char buf[64];
  if (std::fabs(v) < 1e12) {
    for (int decimals = 0; decimals <= 12; ++decimals) {
      std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
      if (std::strtod(buf, nullptr) == v) return buf;
    }
  }
  for (int prec = 1; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

}  // namespace

std::string decimal_problem(const std::string& number) {
  errno = 0;
  const double v = std::strtod(number.c_str(), nullptr);
  const int err = errno;
  if (!std::isfinite(v)) return "'" + number + "' is out of range (beyond 1.8e308)";
  // A mantissa with a digit other than 0 that reads as 0 or a subnormal (1e-400): gone to 0
  // or to a value with fewer digits than a double has.
  const std::size_t e = number.find_first_of("eE");
  const std::string mantissa = number.substr(0, e);
  const bool nonzero = mantissa.find_first_of("123456789") != std::string::npos;
  if (nonzero && (v == 0 || std::fabs(v) < DBL_MIN || err == ERANGE)) {
    return "'" + number + "' is out of range (nonzero and closer to 0 than 2.2e-308)";
  }
  if (v == 0 && std::signbit(v)) return "'" + number + "' is a negative zero; write 0";
  return "";
}

double parse_decimal(const std::string& text, const std::string& what) {
  const std::size_t n = decimal_prefix(text);
  if (n == 0 || n != text.size()) throw UsageError(what + ": '" + text + "' is not a decimal number");
  const std::string problem = decimal_problem(text);
  if (!problem.empty()) throw UsageError(what + ": " + problem);
  return std::strtod(text.c_str(), nullptr);
}

std::size_t decimal_prefix(const std::string& text) {
  std::size_t i = 0;
  const std::size_t n = text.size();
  if (i < n && (text[i] == '+' || text[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < n && is_digit(text[i])) ++i, ++digits;
  if (i < n && text[i] == '.') {
    ++i;
    while (i < n && is_digit(text[i])) ++i, ++digits;
  }
  if (digits == 0) return 0;
  // "0x10": the 'x' ends the number at "0", which callers then reject as a unit or trailing text.
  if (i < n && (text[i] == 'e' || text[i] == 'E')) {
    std::size_t j = i + 1;
    if (j < n && (text[j] == '+' || text[j] == '-')) ++j;
    if (j < n && is_digit(text[j])) {
      while (j < n && is_digit(text[j])) ++j;
      i = j;
    }
  }
  return i;
}

double parse_length(const std::string& text) {
  std::string unit;
  double v = split_number(text, &unit, "length (e.g. 128mm, 0.128m)");
  if (unit.empty() || unit == "m") return v;
  if (unit == "mm") return v * 1e-3;
  if (unit == "cm") return v * 1e-2;
  if (unit == "km") return v * 1e3;
  throw UsageError("'" + text + "': unknown length unit '" + unit + "' (use mm, cm or m)");
}

double parse_angle(const std::string& text) {
  std::string unit;
  double v = split_number(text, &unit, "angle (e.g. 10deg, 0.17rad)");
  if (unit.empty() || unit == "deg") return v * kPi / 180.0;
  if (unit == "rad") return v;
  throw UsageError("'" + text + "': unknown angle unit '" + unit + "' (use deg or rad)");
}

std::string format_length(double metres) {
  if (metres != 0.0 && std::fabs(metres) < 1.0) return shortest(metres * 1e3) + "mm";
  return shortest(metres) + "m";
}

std::string format_angle(double radians) { return shortest(radians / kPi * 180.0) + "deg"; }

}  // namespace canopy::common
