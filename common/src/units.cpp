#include "canopy/common/units.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "canopy/common/error.h"

namespace canopy::common {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Splits "12.5mm" into 12.5 and "mm". Throws on an empty or non-numeric number part.
double split_number(const std::string& text, std::string* suffix, const char* what) {
  const char* begin = text.c_str();
  char* end = nullptr;
  double v = std::strtod(begin, &end);
  if (end == begin || text.empty()) {
    throw UsageError("'" + text + "' is not a " + what);
  }
  *suffix = std::string(end);
  while (!suffix->empty() && suffix->front() == ' ') suffix->erase(suffix->begin());
  if (!std::isfinite(v)) throw UsageError("'" + text + "' is not a finite " + what);
  return v;
}

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
