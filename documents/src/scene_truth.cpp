#include "canopy/documents/scene_truth.h"

#include <cmath>
#include <set>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/json_document.h"
#include "members.h"

namespace canopy::documents {
namespace {

using namespace members;  // NOLINT(google-build-using-namespace): the document's member helpers

TruthPose pose_of(const Json& p, const std::string& w) {
  object(p, w);
  TruthPose pose;
  pose.x = finite_number(at(p, "x", w), w + ".x");
  pose.y = finite_number(at(p, "y", w), w + ".y");
  if (const Json* z = optional(p, "z")) pose.z = finite_number(*z, w + ".z");
  if (const Json* h = optional(p, "heading")) pose.heading = finite_number(*h, w + ".heading");
  return pose;
}

std::string optional_text(const Json& j, const char* key, const std::string& w) {
  const Json* v = optional(j, key);
  return v ? text(*v, path(w, key)) : "";
}

TrueVehicle vehicle_of(const Json& v, const std::string& w) {
  if (!v.is_object()) throw Malformed(w + " must be an object, not " + describe(v));
  TrueVehicle t;
  t.instance = count(at(v, "instance", w), w + ".instance");
  t.model = optional_text(v, "model", w);
  t.cls = optional_text(v, "class", w);
  t.visibility = optional_text(v, "visibility", w);
  if (const Json* p = optional(v, "pose")) t.pose = pose_of(*p, w + ".pose");
  if (const Json* c = optional(v, "canopy_cover")) {
    t.canopy_cover = finite_number(*c, w + ".canopy_cover");
    if (*t.canopy_cover < 0 || *t.canopy_cover > 1) throw Malformed(w + ".canopy_cover must lie in [0, 1]");
  }
  if (const Json* fp = optional(v, "footprint")) {
    if (!fp->is_array() || fp->size() < 3 || fp->size() > 64)
      throw Malformed(w + ".footprint must be a polygon of 3 to 64 [x, y] corners");
    for (std::size_t i = 0; i < fp->size(); ++i) {
      const Json& p = (*fp)[i];
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
        throw Malformed(w + ".footprint[" + std::to_string(i) + "] must be [x, y], not " + describe(p));
      }
      t.footprint.push_back({p[0].get<double>(), p[1].get<double>()});
    }
  }
  return t;
}

TrueClutter clutter_of(const Json& c, const std::string& w) {
  object(c, w);
  TrueClutter t;
  t.kind = text(at(c, "kind", w), w + ".kind");
  const Json& box = at(c, "box", w);
  object(box, w + ".box");
  const auto centre = point3(at(box, "centre", w + ".box"), w + ".box.centre");
  const auto size = point3(at(box, "size", w + ".box"), w + ".box.size");
  if (size[0] < 0 || size[1] < 0 || size[2] < 0) throw Malformed(w + ".box.size must not be negative");
  t.x = centre[0];
  t.y = centre[1];
  t.length = size[0];
  t.width = size[1];
  t.heading = finite_number(at(box, "heading", w + ".box"), w + ".box.heading");
  return t;
}

SceneTruth read_members(const Json& j) {
  SceneTruth t;
  const Json& vs = array(at(j, "vehicles", "truth"), "vehicles");
  std::set<std::int64_t> seen;
  for (std::size_t i = 0; i < vs.size(); ++i) {
    const std::string w = "vehicles[" + std::to_string(i) + "]";
    t.vehicles.push_back(vehicle_of(vs[i], w));
    if (!seen.insert(t.vehicles.back().instance).second)
      throw Malformed(w + ".instance " + std::to_string(t.vehicles.back().instance) + " repeats");
  }
  if (const Json* e = optional(j, "extent")) {
    if (!e->is_array() || e->size() != 2 || !(*e)[0].is_number() || !(*e)[1].is_number())
      throw Malformed("extent must be [X, Y]");
    const double x = (*e)[0].get<double>(), y = (*e)[1].get<double>();
    if (!(x > 0 && y > 0 && std::isfinite(x * y))) throw Malformed("extent must be positive");
    t.extent = std::array<double, 2>{x, y};
  }
  if (const Json* c = optional(j, "clutter")) {
    array(*c, "clutter");
    for (std::size_t i = 0; i < c->size(); ++i)
      t.clutter.push_back(clutter_of((*c)[i], "clutter[" + std::to_string(i) + "]"));
  }
  if (const Json* d = optional(j, "density")) {
    object(*d, "density");
    auto rate = [&](const char* key, std::optional<double>* out) {
      if (const Json* v = optional(*d, key)) {
        *out = finite_number(*v, std::string("density.") + key);
        if (**out < 0) throw Malformed(std::string("density.") + key + " must not be negative");
      }
    };
    rate("pulses_per_m2", &t.pulses_per_m2);
    rate("returns_per_m2", &t.returns_per_m2);
  }
  if (const Json* u = optional(j, "uncertain")) {
    array(*u, "uncertain");
    for (std::size_t i = 0; i < u->size(); ++i) {
      const std::string w = "uncertain[" + std::to_string(i) + "]";
      const TruthPose p = pose_of(at((*u)[i], "pose", w), w + ".pose");
      t.uncertain.push_back({p.x, p.y});
    }
  }
  return t;
}

}  // namespace

SceneTruth read_scene_truth(const std::string& text, const std::string& name) {
  const Json j = formats::open_json_document(text, name, kSceneTruthFormat, nullptr, kSceneTruthVersion);
  try {
    return read_members(j);
  } catch (const Malformed& e) { throw common::DataError(name, e.what()); }
}

SceneTruth read_scene_truth_file(const std::string& path) {
  return read_scene_truth(common::read_file(path), path);
}

namespace {

Json point(const Point3& p) { return Json::array({p[0], p[1], p[2]}); }

Json vehicle_json(const RenderedVehicle& v) {
  Json e;
  e["instance"] = v.instance;
  e["model"] = v.model;
  if (!v.cls.empty()) e["class"] = v.cls;
  e["line"] = v.line;
  e["pose"] = {{"x", v.x},         {"y", v.y},      {"z", v.z}, {"heading", v.heading},
               {"pitch", v.pitch}, {"roll", v.roll}};
  e["size"] = point(v.size);
  Json fp = Json::array();
  for (const auto& p : v.footprint) fp.push_back(Json::array({p[0], p[1]}));
  e["footprint"] = fp;
  e["canopy_cover"] = v.canopy_cover;
  return e;
}

Json clutter_json(const RenderedClutter& c) {
  Json e;
  e["kind"] = c.kind;
  e["box"] = {{"centre", point(c.centre)},
              {"size", point(c.size)},
              {"heading", c.heading},
              {"pitch", c.pitch},
              {"roll", c.roll}};
  return e;
}

void sensor_json(const RenderedSensor& s, Json* j) {
  Json keys = Json::object();
  for (const auto& [k, v] : s.keys) keys[k] = v;
  (*j)["sensor"] = {{"preset", s.preset.empty() ? Json(nullptr) : Json(s.preset)}, {"keys", keys}};
  Json lines = Json::array();
  for (const RenderedFlightLine& l : s.flight_lines) {
    lines.push_back({{"point_source_id", l.point_source_id},
                     {"heading", l.heading},
                     {"offset", l.offset},
                     {"start", point(l.start)},
                     {"end", point(l.end)},
                     {"gps_time", Json::array({l.t0, l.t1})}});
  }
  (*j)["flight_lines"] = lines;
  (*j)["density"] = {{"returns_per_m2", s.returns_per_m2},
                     {"first_returns_per_m2", s.first_returns_per_m2},
                     {"pulses_per_m2", s.pulses_per_m2},
                     {"pulses_by_returns", s.pulses_by_returns}};
}

}  // namespace

std::string write_scene_truth(const RenderedTruth& t, const formats::Provenance& provenance) {
  Json j;
  j["format"] = kSceneTruthFormat;
  j["version"] = kSceneTruthVersion;
  j["provenance"] = formats::provenance_json(provenance);
  j["scene"] = t.scene;
  j["extent"] = Json::array({t.extent_x, t.extent_y});
  j["origin"] = t.origin ? point(*t.origin) : Json(nullptr);
  j["terrain"] = t.terrain;
  j["angles"] = t.angles;
  Json vehicles = Json::array();
  for (const RenderedVehicle& v : t.vehicles) vehicles.push_back(vehicle_json(v));
  j["vehicles"] = vehicles;
  Json clutter = Json::array();
  for (const RenderedClutter& c : t.clutter) clutter.push_back(clutter_json(c));
  j["clutter"] = clutter;
  j["vegetation"] = {
      {"broadleaf", t.broadleaf}, {"conifer", t.conifer}, {"bushes", t.bushes}, {"discs", t.discs}};
  j["canopy_cover"] = t.canopy_cover;
  j["canopy_spacing"] = t.canopy_spacing;
  if (t.sensor) {
    sensor_json(*t.sensor, &j);
  } else {
    Json images = Json::array();
    for (const RenderedImage& v : t.images) {
      images.push_back({{"view_idx", v.view_idx},
                        {"heading", v.heading},
                        {"flight_line", v.flight_line},
                        {"elevation", v.elevation},
                        {"azimuth", v.azimuth},
                        {"toward_sensor", point(v.toward_sensor)},
                        {"swath_area", v.swath_area}});
    }
    j["images"] = images;
  }
  return j.dump(2) + "\n";
}

}  // namespace canopy::documents
