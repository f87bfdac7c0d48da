#include "canopy/documents/areas.h"

#include <cmath>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/json_document.h"
#include "members.h"

namespace canopy::documents {
namespace {

using namespace members;  // NOLINT(google-build-using-namespace): the document's member helpers

double area(double v) { return finite_or_throw(v, "areas"); }

double length(const Json& j, const char* key, bool positive) {
  const Json& v = at(j, key, "areas");
  if (!v.is_number() || v.get<double>() < 0 || (positive && !(v.get<double>() > 0))) {
    throw Malformed(std::string(key) + (positive ? " must be a positive number" : " must be a number >= 0"));
  }
  return v.get<double>();
}

long long integer(const Json& j, const char* key, long long lo) {
  const Json& v = at(j, key, "areas");
  const bool ok = v.is_number_unsigned() || (v.is_number_integer() && v.get<long long>() >= lo);
  if (!ok || v.get<long long>() < lo ||
      v.get<unsigned long long>() > static_cast<unsigned long long>(kAreasMaxCount)) {
    throw Malformed(std::string(key) + " must be an integer in [" + std::to_string(lo) + ", " +
                    std::to_string(kAreasMaxCount) + "]");
  }
  return v.get<long long>();
}

}  // namespace

std::string number_text(double v) { return Json(v).dump(); }

std::string write_areas(const Areas& a, const std::vector<std::string>& inputs) {
  auto num = [](double v) { return number_text(area(v)); };
  std::string s =
      "{\"format\": \"canopy.areas\", \"version\": 1,\n \"provenance\": {\"tool\": \"areas\", "
      "\"version\": \"" CANOPY_VERSION "\", \"inputs\": [";
  for (std::size_t i = 0; i < inputs.size(); ++i) s += (i ? ", " : "") + Json(inputs[i]).dump();
  s += "]},\n \"spacing\": " + num(a.spacing) + ", \"cell\": " + num(a.cell) +
       ", \"voxel\": " + num(a.voxel) + ", \"max_segments\": " + std::to_string(a.max_segments) +
       ",\n \"target_points\": " + std::to_string(a.target_points) +
       ", \"target_samples\": " + std::to_string(a.target_samples) + ",\n \"visible\": " + num(a.visible) +
       ", \"samples\": " + num(a.samples) + ", \"mesh\": " + num(a.mesh) +
       ", \"segments\": " + num(a.segments) + ", \"matched\": " + num(a.matched) + "}\n";
  return s;
}

Areas read_areas(const std::string& text, const std::string& name) {
  const Json j = formats::open_json_document(text, name, kAreasFormat, nullptr, kAreasVersion);
  Areas a;
  try {
    a.visible = length(j, "visible", false);
    a.samples = length(j, "samples", false);
    a.mesh = length(j, "mesh", false);
    a.segments = length(j, "segments", false);
    a.matched = length(j, "matched", false);
    a.spacing = length(j, "spacing", true);
    a.cell = length(j, "cell", true);
    a.voxel = length(j, "voxel", true);
    const long long x = integer(j, "max_segments", 1);
    if (x > kAreasMaxSegments)
      throw Malformed("max_segments must be at most " + std::to_string(kAreasMaxSegments));
    a.max_segments = static_cast<int>(x);
    a.target_points = static_cast<std::size_t>(integer(j, "target_points", 0));
    a.target_samples = static_cast<std::size_t>(integer(j, "target_samples", 0));
  } catch (const Malformed& e) {
    throw common::DataError(name, std::string("bad canopy.areas document: ") + e.what());
  }
  return a;
}

Areas read_areas_file(const std::string& path) { return read_areas(common::read_file(path), path); }

}  // namespace canopy::documents
