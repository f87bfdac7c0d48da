#include "canopy/documents/detections.h"

#include <set>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/json_document.h"
#include "members.h"

namespace canopy::documents {
namespace {

using namespace members;  // NOLINT(google-build-using-namespace): the document's member helpers

constexpr std::int64_t kMaxCount = 1000000000;

std::optional<int> optional_count(const Json& j, const char* key) {
  const Json* v = optional(j, key);
  if (!v) return std::nullopt;
  const std::int64_t n = count(*v, key);
  if (n > kMaxCount) throw Malformed(std::string(key) + " is not a count: " + describe(*v));
  return static_cast<int>(n);
}

std::string optional_text(const Json& j, const char* key, const std::string& w) {
  const Json* v = optional(j, key);
  return v ? text(*v, path(w, key)) : "";
}

std::vector<std::array<double, 2>> footprint(const Json& fp, const std::string& w) {
  if (!fp.is_array() || fp.size() < 3 || fp.size() > 64)
    throw Malformed(w + ".footprint must be a polygon of 3 to 64 [x, y] corners");
  std::vector<std::array<double, 2>> ring;
  for (std::size_t i = 0; i < fp.size(); ++i) {
    const Json& p = fp[i];
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
      throw Malformed(w + ".footprint[" + std::to_string(i) + "] must be [x, y], not " + describe(p));
    }
    ring.push_back({p[0].get<double>(), p[1].get<double>()});
  }
  return ring;
}

Detection read_detection(const Json& e, const std::string& w, int version) {
  if (!e.is_object()) throw Malformed(w + " must be an object, not " + describe(e));
  Detection d;
  d.candidate = text(at(e, "candidate", w), w + ".candidate");
  if (e.contains("level") || version >= 2) {
    const Json& level = at(e, "level", w);
    d.level = level.is_string() ? level.get<std::string>() : "";
    if (d.level != "model" && d.level != "class")
      throw Malformed(w + ".level must be model or class, not " + describe(level));
  } else {
    d.level = e.contains("model") && e["model"].is_null() ? "class" : "model";
  }
  d.model = optional_text(e, "model", w);
  d.cls = optional_text(e, "class", w);
  d.group = optional_text(e, "group", w);
  if (d.level == "class" && d.cls.empty() && d.group.empty())
    throw Malformed(w + ": a class-level detection without a class or group");
  if (const Json* c = optional(e, "confidence")) {
    d.confidence = finite_number(*c, w + ".confidence");
    if (*d.confidence < 0 || *d.confidence > 1) throw Malformed(w + ".confidence must lie in [0, 1]");
  }
  if (const Json* p = optional(e, "pose")) {
    const std::string pw = w + ".pose";
    object(*p, pw);
    d.pose = DetectionPose{
        finite_number(at(*p, "x", pw), pw + ".x"), finite_number(at(*p, "y", pw), pw + ".y"),
        finite_number(at(*p, "z", pw), pw + ".z"), finite_number(at(*p, "heading", pw), pw + ".heading")};
  }
  if (const Json* fp = optional(e, "footprint")) d.footprint = footprint(*fp, w);
  return d;
}

std::map<std::string, int> counts(const Json& o, const char* key) {
  if (!o.is_object()) throw Malformed(std::string(key) + " is not an object");
  std::map<std::string, int> m;
  for (const auto& [k, v] : o.items()) {
    const std::string w = std::string(key) + "." + k;
    const std::int64_t n = count(v, w);
    if (n > kMaxCount) throw Malformed(w + " is not a count: " + describe(v));
    m[k] = static_cast<int>(n);
  }
  return m;
}

Detections read_members(const Json& j) {
  Detections d;
  d.version = j["version"].get<int>();
  const Json& ds = array(at(j, "detections", "detections document"), "detections");
  d.index = optional_text(j, "index", "");
  d.tile = optional_text(j, "tile", "");
  d.candidates = optional_count(j, "candidates");
  d.found = optional_count(j, "found");
  d.none = optional_count(j, "none");
  d.failed = optional_count(j, "failed");
  if (const Json* o = optional(j, "by_level")) d.by_level = counts(*o, "by_level");
  if (const Json* o = optional(j, "by_reason")) d.by_reason = counts(*o, "by_reason");
  if (j.contains("warning")) {
    const Json& w = j["warning"];
    if (!w.is_null() && !w.is_string()) throw Malformed("warning is neither a sentence nor null");
    d.warning = w.is_string() ? w.get<std::string>() : "";
  }
  if (const Json* dens = optional(j, "density")) {
    object(*dens, "density");
    d.density = *dens;
  }
  std::set<std::string> seen;
  for (std::size_t i = 0; i < ds.size(); ++i) {
    const std::string w = "detections[" + std::to_string(i) + "]";
    d.detections.push_back(read_detection(ds[i], w, d.version));
    if (!seen.insert(d.detections.back().candidate).second)
      throw Malformed(w + ".candidate \"" + d.detections.back().candidate + "\" repeats");
  }
  d.has_rejected = j.contains("rejected");
  if (d.has_rejected) {
    const Json& rs = array(j["rejected"], "rejected");
    for (std::size_t i = 0; i < rs.size(); ++i) {
      const std::string w = "rejected[" + std::to_string(i) + "]";
      if (!rs[i].is_object()) throw Malformed(w + " must be an object, not " + describe(rs[i]));
      Rejection r;
      r.candidate = text(at(rs[i], "candidate", w), w + ".candidate");
      if (rs[i].contains("reason")) r.reason = text(rs[i]["reason"], w + ".reason");
      d.rejected.push_back(std::move(r));
    }
  }
  return d;
}

}  // namespace

std::optional<double> Detections::density_all() const {
  if (!density.is_object()) return std::nullopt;
  const auto all = density.find("all");
  if (all == density.end() || !all->is_number() || !(all->get<double>() > 0)) return std::nullopt;
  return all->get<double>();
}

Detections read_detections(const std::string& text, const std::string& name) {
  const Json j = formats::open_json_document(text, name, kDetectionsFormat, nullptr, kDetectionsVersion);
  try {
    return read_members(j);
  } catch (const Malformed& e) { throw common::DataError(name, e.what()); }
}

Detections read_detections_file(const std::string& path) {
  return read_detections(common::read_file(path), path);
}

}  // namespace canopy::documents
