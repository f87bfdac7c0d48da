#include "canopy/documents/candidates.h"

#include <regex>
#include <set>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/json_document.h"
#include "canopy/formats/las_crs.h"
#include "members.h"

namespace canopy::documents {
namespace {

using namespace members;  // NOLINT(google-build-using-namespace): the document's member helpers

std::optional<double> optional_number(const Json& j, const char* key, const std::string& w) {
  const Json* v = optional(j, key);
  return v ? std::optional<double>(finite_number(*v, path(w, key))) : std::nullopt;
}

std::optional<std::int64_t> optional_count(const Json& j, const char* key, const std::string& w) {
  const Json* v = optional(j, key);
  return v ? std::optional<std::int64_t>(count(*v, path(w, key))) : std::nullopt;
}

Candidate read_candidate(const Json& j, const std::string& w, std::set<std::string>& seen, int version) {
  static const std::regex id_ok("[A-Za-z0-9_.-]{1,64}");
  object(j, w);
  if (version >= 2 && j.contains("truth")) {
    throw Malformed(w + ".truth: a version 2 index holds no ground truth (candtruth writes it)");
  }
  Candidate c;
  const Json& id = at(j, "id", w);
  if (!id.is_string()) throw Malformed(w + ".id must be a string");
  c.id = id.get<std::string>();
  // The id names a directory of per-candidate artifacts: no separators, no "..".
  if (!std::regex_match(c.id, id_ok) || c.id == "." || c.id == "..") {
    throw Malformed(w + ".id \"" + c.id + "\" is not a plain name (letters, digits, _ . -)");
  }
  if (!seen.insert(c.id).second) throw Malformed(w + ".id \"" + c.id + "\" repeats");
  if (const Json* f = optional(j, "file")) c.file = text(*f, w + ".file");
  c.transform = rigid_matrix(at(j, "transform", w), w + ".transform");
  if (const Json* v = optional(j, "centre")) c.centre = point3(*v, w + ".centre");
  c.length = finite_number(at(j, "length", w), w + ".length");
  c.width = finite_number(at(j, "width", w), w + ".width");
  if (c.length < 0 || c.width < 0) throw Malformed(w + ": negative footprint");
  c.heading = optional_number(j, "heading", w);
  c.height = optional_number(j, "height", w);
  c.point_count = optional_count(j, "point_count", w);
  c.object_points = optional_count(j, "object_points", w);
  c.density = optional_number(j, "density", w);
  c.planarity = optional_number(j, "planarity", w);
  c.planar_area = optional_number(j, "planar_area", w);
  // "truth" (version 1 only; read_members refuses it in version 2) is dropped unread.
  return c;
}

Candidates read_members(const Json& j, int version) {
  Candidates d;
  d.provenance = j.contains("provenance") ? j["provenance"] : Json();
  if (const Json* t = optional(j, "tile")) d.tile = text(*t, "tile");
  d.tile_points = optional_count(j, "tile_points", "");
  if (const Json* c = optional(j, "crs")) {
    d.crs = text(*c, "crs");
    if (!formats::is_epsg_code(d.crs)) throw Malformed("crs must be EPSG:<code>");
  }
  if (const Json* f = optional(j, "crs_from")) d.crs_from = text(*f, "crs_from");
  if (const Json* ws = optional(j, "warnings")) {
    const Json& a = array(*ws, "warnings");
    for (std::size_t i = 0; i < a.size(); ++i)
      d.warnings.push_back(text(a[i], "warnings[" + std::to_string(i) + "]"));
  }
  if (const Json* o = optional(j, "origin")) d.origin = point3(*o, "origin");
  if (const Json* c = optional(j, "classes")) d.classes = text(*c, "classes");
  if (const Json* g = optional(j, "ground")) {
    object(*g, "ground");
    GroundGrid grid;
    grid.cell = finite_number(at(*g, "cell", "ground"), "ground.cell");
    grid.cells = count(at(*g, "cells", "ground"), "ground.cells");
    for (auto [key, out] : {std::pair{"ground_cells", &grid.ground_cells},
                            {"filled_cells", &grid.filled_cells},
                            {"ground_points", &grid.ground_points}}) {
      if (const Json* v = optional(*g, key)) *out = count(*v, path("ground", key));
    }
    d.ground = grid;
  }
  if (const Json* dens = optional(j, "density")) {
    object(*dens, "density");
    if (const Json* all = optional(*dens, "all")) finite_number(*all, "density.all");
    for (const char* key : {"ground", "first"}) {
      const std::string name = std::string("density.") + key;
      if (const Json* v = optional(*dens, key)) {
        if (finite_number(*v, name) < 0) throw Malformed(name + " must be >= 0 or null");
      }
    }
    d.density = *dens;
  }
  if (const Json* m = optional(j, "margin")) {
    d.margin = finite_number(*m, "margin");
    if (*d.margin < 0) throw Malformed("margin must be >= 0");
  }
  const Json& cs = array(at(j, "candidates", "index"), "candidates");
  std::set<std::string> seen;
  for (std::size_t i = 0; i < cs.size(); ++i) {
    d.candidates.push_back(read_candidate(cs[i], "candidates[" + std::to_string(i) + "]", seen, version));
  }
  // "instances" (version 1's ground truth) is dropped unread; version 2 refuses it.
  if (version >= 2 && j.contains("instances")) {
    throw Malformed("instances: a version 2 index holds no ground truth (candtruth writes it)");
  }
  return d;
}

template <typename T>
const T& need(const std::optional<T>& v, const std::string& what) {
  if (!v) throw common::Error("canopy.candidates writer: " + what + " is not set");
  return *v;
}

}  // namespace

std::optional<double> Candidate::object_density() const {
  if (density) return density;
  if (object_points && length * width > 0) return static_cast<double>(*object_points) / (length * width);
  return std::nullopt;
}

namespace {

// density.KEY when it is a number > 0; none when density is not an object, or KEY is absent, null or 0.
std::optional<double> positive_density(const Json& density, const char* key) {
  if (!density.is_object()) return std::nullopt;
  const auto it = density.find(key);
  if (it == density.end() || !it->is_number() || !(it->get<double>() > 0)) return std::nullopt;
  return it->get<double>();
}

}  // namespace

std::optional<double> Candidates::density_all() const { return positive_density(density, "all"); }

std::optional<double> Candidates::density_ground() const { return positive_density(density, "ground"); }

std::optional<double> Candidates::density_first() const { return positive_density(density, "first"); }

const Candidate* Candidates::find(const std::string& id) const {
  for (const Candidate& c : candidates) {
    if (c.id == id) return &c;
  }
  return nullptr;
}

Candidates read_candidates(const std::string& text, const std::string& name) {
  const Json j = formats::open_json_document(text, name, kCandidatesFormat, nullptr, kCandidatesVersion);
  try {
    return read_members(j, j["version"].get<int>());
  } catch (const Malformed& e) { throw common::DataError(name, e.what()); }
}

Candidates read_candidates_file(const std::string& path) {
  return read_candidates(common::read_file(path), path);
}

std::string Candidates::written_by() const {
  if (!provenance.is_object()) return "";
  const auto it = provenance.find("tool");
  return it != provenance.end() && it->is_string() ? it->get<std::string>() : "";
}

Json detect_density_json(const DetectDensity& d) {
  auto finite = [](double v) { return finite_or_throw(v, "detect"); };
  auto optional = [&](const std::optional<double>& v) { return v ? Json(finite(*v)) : Json(nullptr); };
  return Json{{"all", finite(d.all)},
              {"ground", optional(d.ground)},
              {"first", optional(d.first)},
              {"cell", 1.0},
              {"occupied_cells", d.occupied_cells},
              {"open_ground_cells", d.open_ground_cells},
              {"rule", Json{{"density", finite(d.rule)},
                            {"voxel", finite(d.voxel)},
                            {"voxel_from", d.voxel_by_rule ? "density" : "option"},
                            {"min_planarity", finite(d.min_planarity)},
                            {"min_planarity_from", d.planarity_by_rule ? "density" : "option"},
                            {"dtm_cell", finite(d.dtm_cell)},
                            {"dtm_cell_from", d.cell_by_rule ? "density" : "option"},
                            {"split_rows", d.split_rows},
                            {"split_rows_from", d.split_rows_by_rule ? "density" : "option"},
                            {"row_tolerance", finite(d.row_tolerance)}}}};
}

std::string write_candidates(const Candidates& d, const formats::Provenance& prov) {
  auto finite = [](double v) { return finite_or_throw(v, "detect"); };
  const auto& origin = need(d.origin, "origin");
  const GroundGrid& g = need(d.ground, "ground");
  Json j{{"format", kCandidatesFormat},
         {"version", kCandidatesVersion},
         {"provenance", formats::provenance_json(prov)},
         {"tile", d.tile},
         {"tile_points", need(d.tile_points, "tile_points")}};
  // Only when the tile records a CRS: an index of a tile without one is as before.
  if (!d.crs.empty()) {
    j["crs"] = d.crs;
    j["crs_from"] = d.crs_from;
  }
  // Only when detect warned about the tile: any other index is as before.
  if (!d.warnings.empty()) j["warnings"] = d.warnings;
  j["origin"] = Json::array({finite(origin[0]), finite(origin[1]), finite(origin[2])});
  j["classes"] = d.classes.empty() ? Json(nullptr) : Json(d.classes);
  j["ground"] = Json{{"cell", g.cell},
                     {"cells", g.cells},
                     {"ground_cells", g.ground_cells},
                     {"filled_cells", g.filled_cells},
                     {"ground_points", g.ground_points}};
  j["density"] = d.density;
  j["margin"] = finite(need(d.margin, "margin"));
  Json cands = Json::array();
  for (const Candidate& c : d.candidates) {
    const std::string w = "candidate " + c.id + " ";
    Json t = Json::array();
    for (int row = 0; row < 4; ++row) {
      t.push_back(Json::array({finite(c.transform[4 * row]), finite(c.transform[4 * row + 1]),
                               finite(c.transform[4 * row + 2]), finite(c.transform[4 * row + 3])}));
    }
    const auto& centre = need(c.centre, w + "centre");
    Json cj{{"id", c.id},
            {"file", c.file},
            {"transform", t},
            {"centre", Json::array({centre[0], centre[1], centre[2]})},
            {"length", finite(c.length)},
            {"width", finite(c.width)},
            {"heading", finite(need(c.heading, w + "heading"))},
            {"height", finite(need(c.height, w + "height"))},
            {"point_count", need(c.point_count, w + "point_count")},
            {"object_points", need(c.object_points, w + "object_points")},
            {"density", finite(need(c.density, w + "density"))},
            {"planarity", finite(need(c.planarity, w + "planarity"))},
            {"planar_area", finite(need(c.planar_area, w + "planar_area"))}};
    cands.push_back(std::move(cj));
  }
  j["candidates"] = std::move(cands);
  return j.dump(1) + "\n";
}

}  // namespace canopy::documents
