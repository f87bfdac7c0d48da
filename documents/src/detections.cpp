#include "canopy/documents/detections.h"

#include <set>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/json_document.h"
#include "canopy/formats/las_crs.h"
#include "canopy/formats/provenance.h"
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
  d.model_chain_ran = optional_count(j, "model_chain_ran");
  d.model_chain_failed = optional_count(j, "model_chain_failed");
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
      if (rs[i].contains("confidence") && !rs[i]["confidence"].is_null()) {
        const Json& c = rs[i]["confidence"];
        if (!c.is_number() || !(c.get<double>() >= 0 && c.get<double>() <= 1))
          throw Malformed(w + ".confidence must be a number in [0, 1] or null, not " + describe(c));
        r.confidence = c.get<double>();
      }
      if (rs[i].contains("position") && !rs[i]["position"].is_null()) {
        const Json& q = rs[i]["position"];
        if (!q.is_object())
          throw Malformed(w + ".position must be an object {x, y} or null, not " + describe(q));
        const std::string pw = w + ".position";
        r.position = std::array<double, 2>{finite_number(at(q, "x", pw), pw + ".x"),
                                           finite_number(at(q, "y", pw), pw + ".y")};
      }
      if (rs[i].contains("density") && !rs[i]["density"].is_null()) {
        const Json& q = rs[i]["density"];
        if (!q.is_number() || !(q.get<double>() >= 0))
          throw Malformed(w + ".density must be a number >= 0 or null, not " + describe(q));
        r.density = finite_number(q, w + ".density");
      }
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

namespace {

double finite_number(double v) { return finite_or_throw(v, "collect"); }
Json text_or_null(const std::string& s) { return s.empty() ? Json(nullptr) : Json(s); }
Json number_or_null(const std::optional<double>& v) { return v ? Json(finite_number(*v)) : Json(nullptr); }

Json footprint_json(const DetectionRecord& d) {
  Json fp = Json::array();
  for (const auto& c : d.footprint) fp.push_back(Json::array({finite_number(c[0]), finite_number(c[1])}));
  return fp;
}

Json detection_json(const DetectionRecord& d) {
  const auto& m = d.matrix;
  Json matrix_json = Json::array();
  for (double x : m) matrix_json.push_back(finite_number(x));
  Json pose{{"x", finite_number(m[3])}, {"y", finite_number(m[7])}, {"z", finite_number(m[11])},
            {"heading", d.euler[0]},    {"pitch", d.euler[1]},      {"roll", d.euler[2]},
            {"matrix", matrix_json}};
  Json j{{"candidate", d.candidate},
         {"level", d.model_level ? "model" : "class"},
         {"model", text_or_null(d.model)}};
  if (!d.cls.empty()) j["class"] = d.cls;
  if (!d.group.empty() || !d.model_level) j["group"] = text_or_null(d.group);
  j["confidence"] = d.confidence;
  j["pose"] = pose;
  if (!d.model_level) {
    j["heading_ambiguity_deg"] = finite_number(d.heading_ambiguity);
    j["size"] = d.size ? Json{{"length", finite_number((*d.size)[0])},
                              {"width", finite_number((*d.size)[1])},
                              {"height", finite_number((*d.size)[2])}}
                       : Json(nullptr);
    j["density"] = number_or_null(d.density);
  }
  j["footprint"] = footprint_json(d);
  j["footprint_from"] = d.footprint_from;
  j["verdict"] = d.verdict;
  return j;
}

Json rejection_json(const RejectionRecord& r) {
  Json j{{"candidate", r.candidate}, {"reason", r.reason}};
  j["detail"] = r.detail ? Json(*r.detail) : Json(nullptr);
  j["confidence"] = r.confidence ? Json(*r.confidence) : Json(nullptr);
  if (r.position)
    j["position"] = Json{{"x", finite_number((*r.position)[0])}, {"y", finite_number((*r.position)[1])}};
  j["density"] = number_or_null(r.density);
  if (r.classified) {
    j["density_needed"] = r.has_density_needed ? Json{{"class", number_or_null(r.density_class)},
                                                      {"model", number_or_null(r.density_model)}}
                                               : Json(nullptr);
    j["model_chain"] = r.model_chain ? Json(*r.model_chain) : Json(nullptr);
  }
  j["verdict"] = r.verdict;
  return j;
}

Json feature_json(const DetectionRecord& d) {
  const auto& m = d.matrix;
  Json closed = footprint_json(d);
  closed.push_back(closed[0]);
  Json props{{"candidate", d.candidate},
             {"level", d.model_level ? "model" : "class"},
             {"model", text_or_null(d.model)}};
  if (!d.cls.empty()) props["class"] = d.cls;
  if (!d.group.empty()) props["group"] = d.group;
  props["confidence"] = d.confidence;
  props["x"] = m[3];
  props["y"] = m[7];
  props["z"] = m[11];
  props["heading"] = d.euler[0];
  if (!d.model_level) props["heading_ambiguity_deg"] = d.heading_ambiguity;
  props["footprint_from"] = d.footprint_from;
  return Json{{"type", "Feature"},
              {"id", d.candidate},
              {"geometry", Json{{"type", "Polygon"}, {"coordinates", Json::array({closed})}}},
              {"properties", props}};
}

}  // namespace

std::string serialize_detections(const DetectionsRecord& r) {
  Json dets = Json::array(), rejected = Json::array();
  for (const auto& d : r.detections) dets.push_back(detection_json(d));
  for (const auto& x : r.rejected) rejected.push_back(rejection_json(x));
  Json by_reason = Json::object();
  for (const auto& [reason, k] : r.by_reason) by_reason[reason] = k;
  Json doc{{"format", kDetectionsFormat},
           {"version", kDetectionsVersion},
           {"provenance", formats::provenance_json(r.provenance)},
           {"index", r.index},
           {"tile", r.tile},
           {"crs", text_or_null(r.crs)}};
  if (!r.crs_from.empty()) doc["crs_from"] = r.crs_from;
  doc.update(Json{{"candidates", r.candidates}, {"found", r.found}, {"none", r.none}, {"failed", r.failed}});
  if (r.model_chain_ran) doc["model_chain_ran"] = *r.model_chain_ran;
  if (r.model_chain_failed) doc["model_chain_failed"] = *r.model_chain_failed;
  doc.update(Json{{"by_level", Json{{"model", r.model_level}, {"class", r.class_level}}},
                  {"by_reason", by_reason},
                  {"density", r.density.is_object() ? r.density : Json(nullptr)},
                  {"warning", text_or_null(r.warning)},
                  {"detections", dets},
                  {"rejected", rejected}});
  return doc.dump(1) + "\n";
}

std::string serialize_detections_geojson(const DetectionsRecord& r) {
  Json features = Json::array();
  for (const auto& d : r.detections) features.push_back(feature_json(d));
  Json geo{{"type", "FeatureCollection"}, {"name", "canopy detections"}};
  if (formats::is_epsg_code(r.crs)) {
    // The GeoJSON 2008 "crs" member (RFC 7946 dropped it; GDAL/QGIS still read it).
    geo["crs"] = Json{{"type", "name"}, {"properties", {{"name", "urn:ogc:def:crs:EPSG::" + r.crs.substr(5)}}}};
    if (!r.crs_from.empty()) geo["crs_from"] = r.crs_from;
  }
  geo["features"] = features;
  return geo.dump(1) + "\n";
}

const char* open_ground_density_key(const nlohmann::ordered_json& d) {
  if (!d.is_object()) return nullptr;
  for (const char* key : {"ground", "all"}) {
    if (d.contains(key) && d[key].is_number()) return key;
  }
  return nullptr;
}

std::optional<double> open_ground_density(const nlohmann::ordered_json& d) {
  const char* key = open_ground_density_key(d);
  if (key == nullptr) return std::nullopt;
  return d[key].get<double>();
}

std::optional<double> occupied_hectares(const nlohmann::ordered_json& d) {
  if (!d.is_object() || !d.contains("occupied_cells") || !d["occupied_cells"].is_number())
    return std::nullopt;
  const double cell = d.contains("cell") && d["cell"].is_number() ? d["cell"].get<double>() : 1.0;
  return d["occupied_cells"].get<double>() * cell * cell / 1e4;
}

}  // namespace canopy::documents
