#include "collect/collect.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <set>
#include <stdexcept>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/documents/candidates.h"
#include "canopy/formats/json_document.h"
#include "canopy/formats/provenance.h"
#include "canopy/formats/verdict.h"

namespace canopy::collect {
namespace {

using Json = nlohmann::ordered_json;

using Malformed = formats::MalformedField;
constexpr auto member = formats::json_member;

double number(const Json& v, const std::string& where) {
  if (!v.is_number()) throw Malformed(where + " must be a number, not " + v.dump().substr(0, 40));
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw Malformed(where + " is not finite");
  return d;
}

// A rigid transform: 16 numbers (flat) or 4 rows of 4; the last row 0 0 0 1, the 3 x 3 part a
// rotation (orthonormal within 1e-6, determinant +1).
Matrix matrix(const Json& v, const std::string& where) {
  Matrix m{};
  if (v.is_array() && v.size() == 4 && v[0].is_array()) {
    for (int r = 0; r < 4; ++r) {
      if (!v[r].is_array() || v[r].size() != 4) throw Malformed(where + " must be 4 rows of 4 numbers");
      for (int c = 0; c < 4; ++c) m[4 * r + c] = number(v[r][c], where);
    }
  } else if (v.is_array() && v.size() == 16) {
    for (int i = 0; i < 16; ++i) m[i] = number(v[i], where);
  } else {
    throw Malformed(where + " must be a 4 x 4 matrix (16 numbers or 4 rows of 4)");
  }
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
  return m;
}

Json parse_document(const std::string& text, const std::string& name, const char* format) {
  return formats::open_json_document(text, name, format);
}

Corner apply(const Matrix& m, double x, double y) {
  return {m[0] * x + m[1] * y + m[3], m[4] * x + m[5] * y + m[7]};
}

double finite(double v) {
  if (!std::isfinite(v)) throw common::Error("collect: refusing to write a non-finite number");
  return v;
}

}  // namespace

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix p{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[4 * r + k] * b[4 * k + c];
      p[4 * r + c] = s;
    }
  }
  return p;
}

std::array<double, 3> euler_degrees(const Matrix& m) {
  const double deg = 180 / common::kPi;
  const double heading = std::atan2(m[4], m[0]);
  const double pitch = std::asin(std::max(-1.0, std::min(1.0, -m[8])));
  const double roll = std::atan2(m[9], m[10]);
  return {heading * deg, pitch * deg, roll * deg};
}

Index parse_index(const std::string& text, const std::string& name) {
  const documents::Candidates doc = documents::read_candidates(text, name);
  Index index;
  index.name = name;
  index.tile = doc.tile;
  for (const documents::Candidate& d : doc.candidates) {
    index.candidates.push_back(Candidate{d.id, d.transform, d.length, d.width, d.object_density()});
  }
  index.density = doc.density;
  return index;
}

Verdict absent_verdict(const std::string& name) {
  Verdict v;
  v.name = name;
  v.present = false;
  return v;
}

namespace {

// classify's keys of a verdict (docs/decisions/classify.md §9), each optional.
void parse_class_keys(const Json& j, Verdict& v) {
  auto name_or_null = [&](const char* key, std::string& out) {
    if (!j.contains(key) || j[key].is_null()) return;
    if (!j[key].is_string() || !formats::is_model_name(j[key].get<std::string>())) {
      throw Malformed(std::string(key) + " must be a name or null");
    }
    out = j[key].get<std::string>();
  };
  name_or_null("level", v.level);
  name_or_null("group", v.group);
  name_or_null("reason", v.reason);
  if (j.contains("detail") && j["detail"].is_string()) v.detail = j["detail"].get<std::string>();
  auto optional = [&](const Json& o, const char* key, const std::string& where) -> std::optional<double> {
    if (!o.is_object() || !o.contains(key) || o[key].is_null()) return std::nullopt;
    return number(o[key], where);
  };
  v.density = optional(j, "density", "density");
  if (j.contains("density_needed") && j["density_needed"].is_object()) {
    v.density_class = optional(j["density_needed"], "class", "density_needed.class");
    v.density_model = optional(j["density_needed"], "model", "density_needed.model");
  }
  v.heading_ambiguity = optional(j, "heading_ambiguity_deg", "heading_ambiguity_deg");
  if (j.contains("size") && !j["size"].is_null()) {
    const Json& sz = j["size"];
    if (!sz.is_array() || sz.size() != 3) throw Malformed("size must be [L, W, H] or null");
    std::array<double, 3> lwh{};
    for (int k = 0; k < 3; ++k) {
      lwh[k] = number(sz[k], "size");
      if (lwh[k] < 0) throw Malformed("size must not be negative");
    }
    v.size = lwh;
  }
}

}  // namespace

Verdict parse_verdict(const std::string& text, const std::string& name) {
  if (text.empty()) {
    Verdict failed;
    failed.name = name;
    failed.failed = true;
    return failed;
  }
  const Json j = parse_document(text, name, "canopy.verdict");
  Verdict v;
  v.name = name;
  try {
    const Json& candidate = member(j, "candidate", "verdict");
    if (!candidate.is_string() || candidate.get<std::string>().empty()) {
      throw Malformed("candidate must name the candidate's points (verify --points)");
    }
    v.candidate = candidate.get<std::string>();
    const Json& model = member(j, "model", "verdict");
    if (!model.is_null() && !(model.is_string() && formats::is_model_name(model.get<std::string>()))) {
      throw Malformed(
          "model must be a model name (a file stem: no '/', not . or .., no control characters) or null, "
          "not " +
          model.dump(-1, ' ', true, Json::error_handler_t::replace).substr(0, 60));
    }
    if (model.is_string()) v.model = model.get<std::string>();
    v.confidence = number(member(j, "confidence", "verdict"), "confidence");
    if (v.confidence < 0 || v.confidence > 1) throw Malformed("confidence must lie in [0, 1]");
    if (j.contains("class") && !j["class"].is_null()) {
      if (!j["class"].is_string() || !formats::is_model_name(j["class"].get<std::string>())) {
        throw Malformed("class must be a class name or null");
      }
      v.cls = j["class"].get<std::string>();
    }
    for (const char* key : {"pose", "pose_tile"}) {
      if (!j.contains(key) || j[key].is_null()) continue;
      const Matrix m = matrix(member(j[key], "matrix", key), std::string(key) + ".matrix");
      (std::string(key) == "pose" ? v.pose : v.pose_tile) = m;
    }
    parse_class_keys(j, v);
    if (!v.model.empty() && !v.pose && !v.pose_tile) throw Malformed("a model without a pose");
    if (v.model.empty() && !v.cls.empty() && v.level == "class" && !v.pose && !v.pose_tile) {
      throw Malformed("a class without a pose");
    }
  } catch (const Malformed& e) { throw common::DataError(name, e.what()); }
  return v;
}

bool names_candidate(const std::string& points, const std::string& id) {
  const std::filesystem::path p(points);
  return p.stem() == id || p.parent_path().filename() == id;
}

void check_verdict_of(const Verdict& v, const std::string& id, const std::string& index_dir) {
  if (v.failed || !v.present) return;
  if (!names_candidate(v.candidate, id)) {
    throw common::DataError(v.name, "was written for \"" + v.candidate + "\", not for candidate " + id +
                                        " (its points are " + id + ".pcd or " + id + "/<file>)");
  }
  // When the points are there to look at, they must be this tile's: detect's <id>.pcd beside
  // the index, or a file in the candidate's directory (beside the index or the verdict).
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path points(v.candidate);
  if (!fs::exists(points, ec)) return;
  const fs::path dir = points.parent_path().empty() ? fs::path(".") : points.parent_path();
  const fs::path index = index_dir.empty() ? fs::path(".") : fs::path(index_dir);
  const fs::path verdict_dir =
      fs::path(v.name).parent_path().empty() ? fs::path(".") : fs::path(v.name).parent_path();
  auto same = [&](const fs::path& a, const fs::path& b) {
    std::error_code e;
    return fs::equivalent(a, b, e) && !e;
  };
  if ((points.stem() == id && same(dir, index)) || same(dir, index / id) || same(dir, verdict_dir)) return;
  throw common::DataError(v.name, "was written for " + v.candidate + ", which is not candidate " + id +
                                      " of this tile (not " + (index / (id + ".pcd")).string() + " nor in " +
                                      (index / id).string() + "/ or " + verdict_dir.string() + "/)");
}

std::string plan(const Index& index, const std::string& key, double model_density) {
  std::string out =
      "# generated by collect --plan from " + index.name + "; read by mk/scenes.mk\n" + key + "_CANDS :=";
  for (const auto& c : index.candidates) out += " " + c.id;
  out += "\n";
  for (const auto& c : index.candidates) {
    out += key + "_TRANSFORM_" + c.id + " :=";
    for (int i = 0; i < 16; ++i) {
      char buf[40];
      std::snprintf(buf, sizeof buf, "%s%.17g", i ? "," : " ", c.transform[i]);
      out += buf;
    }
    out += "\n";
  }
  for (const auto& c : index.candidates) {
    const bool model = !c.density || *c.density >= model_density;
    out += key + "_LEVEL_" + c.id + " := " + (model ? "model" : "class") + "\n";
  }
  return out;
}

namespace {

// A found vehicle placed in the tile: its model -> tile pose, the pose's angles and its
// footprint (counter-clockwise corners) from the model's box or the candidate's.
struct Placement {
  Matrix m{};
  std::array<double, 3> e{};
  std::vector<Corner> ring;
  std::string from;
};

Placement place(const Candidate& c, const Verdict& v, const Params& params) {
  Placement p;
  // The tile pose: the verdict's pose_tile when it was given the transform, else composed here.
  p.m = v.pose_tile ? *v.pose_tile : multiply(c.transform, *v.pose);
  p.e = euler_degrees(p.m);
  const Matrix& m = p.m;
  const auto box = v.model.empty() ? params.boxes.end() : params.boxes.find(v.model);
  if (v.model.empty() && v.size) {
    // A class-level answer: its measured rectangle (±L/2, ±W/2) about the pose.
    const double hl = (*v.size)[0] / 2, hw = (*v.size)[1] / 2;
    p.ring = {apply(m, -hl, -hw), apply(m, hl, -hw), apply(m, hl, hw), apply(m, -hl, hw)};
    p.from = "class";
  } else if (box != params.boxes.end()) {
    const ModelBox& b = box->second;
    p.ring = {apply(m, b.x0, b.y0), apply(m, b.x1, b.y0), apply(m, b.x1, b.y1), apply(m, b.x0, b.y1)};
    p.from = "model";
  } else {
    const double hl = c.length / 2, hw = c.width / 2;
    const Matrix& t = c.transform;
    p.ring = {apply(t, -hl, -hw), apply(t, hl, -hw), apply(t, hl, hw), apply(t, -hl, hw)};
    p.from = "candidate";
  }
  // Counter-clockwise seen from above (RFC 7946 exterior rings); the shoelace relative to
  // the first corner, as products of UTM magnitudes would cancel.
  auto& ring = p.ring;
  double area2 = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const Corner& a = ring[k];
    const Corner& b = ring[(k + 1) % 4];
    area2 += (a[0] - ring[0][0]) * (b[1] - ring[0][1]) - (b[0] - ring[0][0]) * (a[1] - ring[0][1]);
  }
  if (area2 < 0) std::swap(ring[1], ring[3]);
  return p;
}

Json footprint_json(const Placement& p) {
  Json fp = Json::array();
  for (const auto& c : p.ring) fp.push_back(Json::array({finite(c[0]), finite(c[1])}));
  return fp;
}

Json text_or_null(const std::string& s) { return s.empty() ? Json(nullptr) : Json(s); }
Json number_or_null(const std::optional<double>& v) { return v ? Json(finite(*v)) : Json(nullptr); }

// The detection's entry in detections.json: model level (the model chain's verdict names a
// model) or class level (classify's answer names a class; "model": null).
Json detection_json(const Candidate& c, const Verdict& v, const Placement& p) {
  const Matrix& m = p.m;
  const auto& e = p.e;
  const bool model = !v.model.empty();
  Json matrix_json = Json::array();
  for (double x : m) matrix_json.push_back(finite(x));
  Json pose{{"x", finite(m[3])}, {"y", finite(m[7])}, {"z", finite(m[11])},   {"heading", e[0]},
            {"pitch", e[1]},     {"roll", e[2]},      {"matrix", matrix_json}};
  Json d{{"candidate", c.id}, {"level", model ? "model" : "class"}, {"model", text_or_null(v.model)}};
  if (!v.cls.empty()) d["class"] = v.cls;
  if (!v.group.empty() || !model) d["group"] = text_or_null(v.group);
  d["confidence"] = v.confidence;
  d["pose"] = pose;
  if (!model) {
    d["heading_ambiguity_deg"] = v.heading_ambiguity ? finite(*v.heading_ambiguity) : 180.0;
    d["size"] = v.size ? Json{{"length", finite((*v.size)[0])},
                              {"width", finite((*v.size)[1])},
                              {"height", finite((*v.size)[2])}}
                       : Json(nullptr);
    d["density"] = number_or_null(v.density);
  }
  d["footprint"] = footprint_json(p);
  d["footprint_from"] = p.from;
  d["verdict"] = v.name;
  return d;
}

// The detection as a GeoJSON Feature: its footprint polygon (closed ring) and properties.
Json feature_json(const Candidate& c, const Verdict& v, const Placement& p) {
  const Matrix& m = p.m;
  Json closed = footprint_json(p);
  closed.push_back(closed[0]);
  Json props{
      {"candidate", c.id}, {"level", v.model.empty() ? "class" : "model"}, {"model", text_or_null(v.model)}};
  if (!v.cls.empty()) props["class"] = v.cls;
  if (!v.group.empty()) props["group"] = v.group;
  props["confidence"] = v.confidence;
  props["x"] = m[3];
  props["y"] = m[7];
  props["z"] = m[11];
  props["heading"] = p.e[0];
  if (v.model.empty()) props["heading_ambiguity_deg"] = v.heading_ambiguity ? *v.heading_ambiguity : 180.0;
  props["footprint_from"] = p.from;
  return Json{{"type", "Feature"},
              {"id", c.id},
              {"geometry", Json{{"type", "Polygon"}, {"coordinates", Json::array({closed})}}},
              {"properties", props}};
}

// The rejection of a candidate no level answered: classify's reason when it answered, else
// the model chain's none or failure.
Json rejection_json(const Candidate& c, const Answers& a, std::string& reason) {
  const Verdict& k = a.cls;
  const Verdict& v = a.model;
  const bool classified = k.present && !k.failed;
  const bool failed = v.present ? v.failed : k.failed;
  reason = classified ? (k.reason.empty() ? "none" : k.reason) : (failed ? "failed" : "none");
  Json r{{"candidate", c.id}, {"reason", reason}};
  if (classified) {
    r["detail"] = k.detail.empty() ? Json(nullptr) : Json(k.detail);
    r["confidence"] = k.confidence;
    r["density"] = number_or_null(k.density ? k.density : c.density);
    Json needed = nullptr;
    if (k.density_class || k.density_model) {
      needed = Json{{"class", number_or_null(k.density_class)}, {"model", number_or_null(k.density_model)}};
    }
    r["density_needed"] = needed;
    // What the model chain said, when it ran.
    r["model_chain"] = !v.present ? Json(nullptr) : Json(v.failed ? "failed" : "none");
    r["verdict"] = k.name;
  } else {
    r["detail"] = reason == "failed" ? "a stage of the model chain failed (see the candidate's .log files)"
                                     : "the model chain found no model of the modelbase";
    r["confidence"] = reason == "failed" || !v.present ? Json(nullptr) : Json(v.confidence);
    r["density"] = number_or_null(c.density);
    r["verdict"] = v.present ? v.name : k.name;
  }
  return r;
}

std::string fmt_density(double d) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f", d);
  return buf;
}

// The tile's density for messages: open ground's, else all points' (detect.md §7).
std::optional<double> tile_density(const Index& index) {
  const Json& d = index.density;
  if (!d.is_object()) return std::nullopt;
  for (const char* key : {"ground", "all"}) {
    if (d.contains(key) && d[key].is_number()) return d[key].get<double>();
  }
  return std::nullopt;
}

// One sentence when most candidates were rejected for one reason (with what would help), or
// when no candidate reached the model level because the data is too sparse for it.
std::string warning_of(const Index& index, const std::vector<Answers>& answers, const Output& out,
                       const std::vector<std::string>& reasons) {
  const int n = static_cast<int>(index.candidates.size());
  if (n == 0) return "";
  const auto td = tile_density(index);
  const std::string tile = td ? "tile density " + fmt_density(*td) + " points/m²" : "";
  // Densities and thresholds of the candidates classify answered.
  std::vector<double> dens;
  std::optional<double> need_class, need_model;
  for (std::size_t i = 0; i < answers.size(); ++i) {
    const Verdict& k = answers[i].cls;
    if (!k.present || k.failed) continue;
    if (reasons[i] == "too_sparse" && k.density) dens.push_back(*k.density);
    if (k.density_class) need_class = k.density_class;
    if (k.density_model) need_model = k.density_model;
  }
  std::vector<std::string> parts;
  std::string top;
  int top_n = 0;
  for (const auto& [r, k] : out.by_reason) {
    if (k > top_n) top = r, top_n = k;
  }
  if (2 * top_n > n) {
    std::string s = std::to_string(top_n) + " of " + std::to_string(n) + " candidates rejected as " + top;
    if (top == "too_sparse") {
      std::sort(dens.begin(), dens.end());
      if (!dens.empty()) {
        const std::size_t h = dens.size() / 2;
        const double median = dens.size() % 2 ? dens[h] : 0.5 * (dens[h - 1] + dens[h]);
        s += " (median object density " + fmt_density(median) + " points/m²";
      }
      if (need_class)
        s += std::string(dens.empty() ? " (" : ", ") + "class level needs " + fmt_density(*need_class);
      if (need_model) s += ", model level " + fmt_density(*need_model);
      if (!dens.empty() || need_class) s += ")";
      s += ": the survey is too sparse for these objects; a denser survey is the remedy";
    } else if (top == "failed") {
      s += ": a stage of the model chain failed; see cands/<id>/*.log";
    } else if (top == "none") {
      s += ": the model chain found no model of the modelbase in them";
    } else if (top == "vegetation_like") {
      s += ": most candidates look like vegetation (porous, rough, pulses through them)";
    } else {
      s += " by classify's size and shape gates";
    }
    parts.push_back(s);
  }
  // No model chain ran (every candidate class level) because the objects are too sparse.
  int model_runs = 0;
  for (const auto& a : answers) model_runs += a.model.present ? 1 : 0;
  if (model_runs == 0) {
    const double need = need_model ? *need_model : kModelDensity;
    parts.push_back((tile.empty() ? std::string("the objects' density") : tile) + ": below the " +
                    fmt_density(need) +
                    " points/m² that model-level recognition needs; class-level answers only");
  }
  if (parts.empty()) return "";
  std::string w;
  for (const auto& p : parts) w += (w.empty() ? "" : "; ") + p;
  return w + "; see docs/decisions/classify.md";
}

// detections.json and the GeoJSON FeatureCollection of the counted detections.
void write_documents(const Index& index, const Params& params, const Json& provenance, const Json& dets,
                     const Json& rejected, const Json& features, Output& out) {
  Json by_reason = Json::object();
  for (const auto& [r, k] : out.by_reason) by_reason[r] = k;
  Json doc{{"format", "canopy.detections"},
           {"version", 2},
           {"provenance", provenance},
           {"index", index.name},
           {"tile", index.tile},
           {"crs", params.crs.empty() ? Json(nullptr) : Json(params.crs)},
           {"candidates", index.candidates.size()},
           {"found", out.found},
           {"none", out.none},
           {"failed", out.failed},
           {"by_level", Json{{"model", out.model_level}, {"class", out.class_level}}},
           {"by_reason", by_reason},
           {"density", index.density.is_object() ? index.density : Json(nullptr)},
           {"warning", out.warning.empty() ? Json(nullptr) : Json(out.warning)},
           {"detections", dets},
           {"rejected", rejected}};
  out.detections = doc.dump(1) + "\n";
  Json geo{{"type", "FeatureCollection"}, {"name", "canopy detections"}};
  if (!params.crs.empty()) {
    // The GeoJSON 2008 "crs" member (RFC 7946 dropped it; GDAL/QGIS still read it).
    geo["crs"] =
        Json{{"type", "name"}, {"properties", {{"name", "urn:ogc:def:crs:EPSG::" + params.crs.substr(5)}}}};
  }
  geo["features"] = features;
  out.geojson = geo.dump(1) + "\n";
}

std::string summary_line(const Index& index, const Output& out) {
  std::string s = std::to_string(index.candidates.size()) + " candidates: " + std::to_string(out.found) +
                  " vehicles found (" + std::to_string(out.model_level) + " model level, " +
                  std::to_string(out.class_level) + " class level)";
  if (!out.by_reason.empty()) {
    s += "; rejected:";
    bool first = true;
    for (const auto& [r, k] : out.by_reason) {
      s += std::string(first ? " " : ", ") + r + " " + std::to_string(k);
      first = false;
    }
  }
  return s;
}

}  // namespace

void validate(const Params& params) {
  if (!params.crs.empty() && !std::regex_match(params.crs, std::regex("EPSG:[0-9]{1,6}"))) {
    throw common::UsageError("--crs must be EPSG:<code>, e.g. EPSG:32633");
  }
}

Output collect(const Index& index, const std::vector<Answers>& answers, const Params& params,
               const Json& provenance) {
  if (answers.size() != index.candidates.size())
    throw common::Error("collect: one answer per candidate expected");
  Json dets = Json::array(), rejected = Json::array(), features = Json::array();
  Output out;
  std::vector<std::string> reasons(answers.size());
  for (std::size_t i = 0; i < answers.size(); ++i) {
    const Candidate& c = index.candidates[i];
    const Verdict& v = answers[i].model;
    const Verdict& k = answers[i].cls;
    for (const Verdict* x : {&v, &k}) {
      if (x->present && !x->failed && !names_candidate(x->candidate, c.id)) {
        throw common::DataError(x->name, "was written for \"" + x->candidate + "\", not for candidate " + c.id);
      }
    }
    if (!v.present && !k.present) {
      throw common::DataError(v.name, "does not exist, nor does " + k.name + ": candidate " + c.id +
                                          " has no answer (run its model chain or classify)");
    }
    const Verdict* found = nullptr;
    if (v.present && !v.failed && !v.model.empty()) {
      found = &v;
      ++out.model_level;
    } else if (k.present && !k.failed && !k.cls.empty() && (k.pose || k.pose_tile)) {
      found = &k;
      ++out.class_level;
    }
    if (found) {
      ++out.found;
      const Placement p = place(c, *found, params);
      dets.push_back(detection_json(c, *found, p));
      features.push_back(feature_json(c, *found, p));
      continue;
    }
    rejected.push_back(rejection_json(c, answers[i], reasons[i]));
    ++out.by_reason[reasons[i]];
    // v1's counts: a failed model chain with no class answer, else a "none" (someone looked).
    if (reasons[i] == "failed") {
      ++out.failed;
    } else {
      ++out.none;
    }
  }
  out.warning = warning_of(index, answers, out, reasons);
  out.summary = summary_line(index, out);
  write_documents(index, params, provenance, dets, rejected, features, out);
  return out;
}

Output run(const Params& params, const Inputs& inputs) {
  return collect(inputs.index, inputs.answers, params, formats::provenance_json(inputs.provenance));
}

}  // namespace canopy::collect
