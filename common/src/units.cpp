#include "canopy/common/units.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "canopy/common/error.h"
#include "canopy/common/math.h"

namespace canopy::common {
namespace {

// Splits "12.5mm" into 12.5 and "mm". Throws on an empty or non-decimal number part.
double split_number(const std::string& text, std::string* suffix, const char* what) {
  const std::size_t n = decimal_prefix(text);
  if (n == 0) throw UsageError("'" + text + "' is not a " + what);
  const double v = std::strtod(text.substr(0, n).c_str(), nullptr);
  *suffix = text.substr(n);
  while (!suffix->empty() && suffix->front() == ' ') suffix->erase(suffix->begin());
  if (!std::isfinite(v)) throw UsageError("'" + text + "' is not a finite " + what);
  return v;
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
