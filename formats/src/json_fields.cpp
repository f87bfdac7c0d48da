#include "canopy/formats/json_fields.h"

#include <cmath>
#include <cstdint>

#include "binary_io.h"
#include "canopy/common/error.h"

namespace canopy::formats {

using Json = nlohmann::ordered_json;

std::string json_describe(const Json& j) {
  if (j.is_array()) return "an array";
  if (j.is_object()) return "an object";
  return detail::quote(j.dump(), 40);
}

std::string json_library_text(const std::exception& e) {
  std::string w = e.what();
  if (w.rfind("[json.exception.", 0) == 0 && w.find("] ") != std::string::npos)
    w = w.substr(w.find("] ") + 2);
  return detail::quote(w, 200);
}

long long json_integer(const Json& j, const std::string& what, long long lo, long long hi) {
  long long v = 0;
  if (j.is_number_unsigned()) {
    const auto u = j.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(hi)) throw MalformedField(what + " " + j.dump() + " is out of range");
    v = static_cast<long long>(u);
  } else if (j.is_number_integer()) {
    v = j.get<std::int64_t>();
  } else {
    throw MalformedField(what + " must be an integer, not " + json_describe(j));
  }
  if (v < lo || v > hi) {
    throw MalformedField(what + " " + j.dump() + " is out of range [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "]");
  }
  return v;
}

int json_int_at(const Json& obj, const char* key, const std::string& where, long long lo) {
  return static_cast<int>(json_integer(obj.at(key), where + key, lo));
}

double json_number_at(const Json& obj, const char* key, const std::string& where) {
  const Json& j = obj.at(key);
  if (!j.is_number()) throw MalformedField(where + key + " must be a number, not " + json_describe(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw MalformedField(where + key + " is not finite");
  return v;
}

std::string json_string_at(const Json& obj, const char* key, const std::string& where) {
  const Json& j = obj.at(key);
  if (!j.is_string()) throw MalformedField(where + key + " must be a string");
  return j.get<std::string>();
}

const Json& json_array_at(const Json& obj, const char* key, const std::string& where) {
  const Json& j = obj.at(key);
  if (!j.is_array()) throw MalformedField(where + key + " must be an array");
  return j;
}

std::array<double, 3> json_vec3_at(const Json& obj, const char* key, const std::string& where) {
  const Json& j = obj.at(key);
  if (!j.is_array() || j.size() != 3) throw MalformedField(where + key + " must be an array of 3 numbers");
  std::array<double, 3> v{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!j[i].is_number()) throw MalformedField(where + key + " must be an array of 3 numbers");
    v[i] = j[i].get<double>();
  }
  return v;
}

Provenance json_provenance(const Json& j) {
  Provenance p;
  if (!j.is_object()) throw MalformedField("provenance must be an object");
  p.tool = json_string_at(j, "tool", "provenance.");
  p.version = json_string_at(j, "version", "provenance.");
  const Json& params = j.at("parameters");
  if (!params.is_object()) throw MalformedField("provenance.parameters must be an object");
  for (const auto& [k, v] : params.items()) {
    if (!v.is_string()) throw MalformedField("provenance.parameters." + k + " must be a string");
    p.parameters.emplace_back(k, v.get<std::string>());
  }
  for (const auto& in : json_array_at(j, "inputs", "provenance.")) {
    if (!in.is_string()) throw MalformedField("provenance.inputs must be strings");
    p.inputs.push_back(in.get<std::string>());
  }
  return p;
}

double finite_for_writing(double v, const char* what) {
  if (!std::isfinite(v)) throw common::Error(std::string("refusing to write non-finite ") + what);
  return v;
}

std::string json_document_text(const Json& j) { return j.dump(1) + "\n"; }

}  // namespace canopy::formats
