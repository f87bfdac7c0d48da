#include "members.h"

#include <cmath>
#include <exception>

#include "canopy/common/error.h"
#include "canopy/formats/json_fields.h"

namespace canopy::documents::members {

std::string describe(const Json& v) {
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  std::string s = v.dump(-1, ' ', true, Json::error_handler_t::replace);
  return s.size() > 40 ? s.substr(0, 40) + "..." : s;
}

std::string path(const std::string& where, const char* key) {
  return where.empty() ? std::string(key) : where + "." + key;
}

const Json& at(const Json& j, const char* key, const std::string& where) {
  return formats::json_member(j, key, where.empty() ? "document" : where);
}

const Json* optional(const Json& j, const char* key) {
  if (!j.is_object()) return nullptr;
  const auto it = j.find(key);
  return it == j.end() || it->is_null() ? nullptr : &*it;
}

double finite_number(const Json& v, const std::string& what) {
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    throw Malformed(what + " must be a finite number, not " + describe(v));
  return v.get<double>();
}

std::int64_t count(const Json& v, const std::string& what) {
  const bool ok = v.is_number_unsigned() || (v.is_number_integer() && v.get<long long>() >= 0);
  if (!ok || v.get<unsigned long long>() > (1ULL << 53))
    throw Malformed(what + " must be a non-negative integer, not " + describe(v));
  return v.get<std::int64_t>();
}

std::string text(const Json& v, const std::string& what) {
  if (!v.is_string()) throw Malformed(what + " must be a string, not " + describe(v));
  return v.get<std::string>();
}

const Json& array(const Json& v, const std::string& what) {
  if (!v.is_array()) throw Malformed(what + " must be an array, not " + describe(v));
  return v;
}

const Json& object(const Json& v, const std::string& what) {
  if (!v.is_object()) throw Malformed(what + " must be an object, not " + describe(v));
  return v;
}

std::array<double, 3> point3(const Json& v, const std::string& what) {
  if (!v.is_array() || v.size() != 3) throw Malformed(what + " must be [x, y, z], not " + describe(v));
  return {finite_number(v[0], what), finite_number(v[1], what), finite_number(v[2], what)};
}

std::array<double, 16> rigid_matrix(const Json& v, const std::string& where) {
  std::array<double, 16> m{};
  if (v.is_array() && v.size() == 4 && v[0].is_array()) {
    for (int r = 0; r < 4; ++r) {
      if (!v[r].is_array() || v[r].size() != 4) throw Malformed(where + " must be 4 rows of 4 numbers");
      for (int c = 0; c < 4; ++c) m[4 * r + c] = finite_number(v[r][c], where);
    }
  } else if (v.is_array() && v.size() == 16) {
    for (int i = 0; i < 16; ++i) m[i] = finite_number(v[i], where);
  } else {
    throw Malformed(where + " must be a 4 x 4 matrix (16 numbers or 4 rows of 4)");
  }
  check_rigid(m, where);
  return m;
}

void check_rigid(const std::array<double, 16>& m, const std::string& where) {
  if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
    throw Malformed(where + ": last row is not 0 0 0 1");
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += m[4 * k + a] * m[4 * k + b];
      if (std::fabs(dot - (a == b ? 1 : 0)) > 1e-6)
        throw Malformed(where + ": the 3 x 3 part is not a rotation");
    }
  }
  const double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                     m[2] * (m[4] * m[9] - m[5] * m[8]);
  if (det < 0) throw Malformed(where + ": the 3 x 3 part is a reflection");
}

double finite_or_throw(double v, const char* tool) {
  if (!std::isfinite(v)) throw common::Error(std::string(tool) + ": refusing to write a non-finite number");
  return v;
}

std::string item(const std::string& prefix, const char* key, std::size_t k) {
  return prefix + key + "[" + std::to_string(k) + "].";
}

const Json& item_object(const Json& v, const std::string& item) {
  if (!v.is_object()) throw Malformed(item.substr(0, item.size() - 1) + " must be an object");
  return v;
}

void rethrow_malformed(const std::string& name, const char* what) {
  try {
    throw;
  } catch (const common::DataError&) { throw; } catch (const Malformed& e) {
    throw common::DataError(name, std::string("malformed ") + what + ": " + e.what());
  } catch (const std::exception& e) {
    throw common::DataError(name, std::string("malformed ") + what + ": " + formats::json_library_text(e));
  }
  throw;  // not reached: every handler above throws, anything else propagates
}

}  // namespace canopy::documents::members
