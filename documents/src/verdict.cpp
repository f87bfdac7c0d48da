#include "canopy/documents/verdict.h"

#include "canopy/formats/json_document.h"
#include "canopy/formats/provenance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <nlohmann/json.hpp>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "members.h"
#include "verdict_json.h"

namespace canopy::documents {

namespace verdict_json {

namespace {
double finite_pose(double v) {
  if (!std::isfinite(v)) throw common::Error("refusing to write non-finite pose");
  return v;
}
}  // namespace

nlohmann::ordered_json pose_json(const Pose& p) {
  using Json = nlohmann::ordered_json;
  Json m = Json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m.push_back(finite_pose(p.rotation[3 * r + c]));
    m.push_back(finite_pose(p.translation[r]));
  }
  for (double v : {0.0, 0.0, 0.0, 1.0}) m.push_back(v);
  const auto e = formats::euler_degrees(p);
  return Json{{"matrix", m},
              {"translation", Json::array({p.translation[0], p.translation[1], p.translation[2]})},
              {"heading_deg", e[0]},
              {"pitch_deg", e[1]},
              {"roll_deg", e[2]}};
}

}  // namespace verdict_json

namespace {

using formats::MalformedField;
using formats::open_json_document;
using formats::provenance_json;

using common::DataError;
using Json = nlohmann::ordered_json;

constexpr const char* kFormat = kVerdictFormat;
constexpr int kVersion = kVerdictVersion;

double finite(double v, const char* what) {
  if (!std::isfinite(v)) throw common::Error(std::string("refusing to write non-finite ") + what);
  return v;
}

using verdict_json::pose_json;

// A malformed member: parse_verdict adds the file ("malformed verdict: hypotheses[1].score ...").
using Malformed = MalformedField;

using members::describe;

const Json& at(const Json& j, const char* key, const std::string& where) {
  return formats::json_member(j, key, where.empty() ? "verdict" : where);
}

// "<where>.<key>", or key alone at the top.
std::string name_of(const std::string& where, const char* key) { return members::path(where, key); }

// A finite number (JSON has no NaN; numbers beyond double's range are refused when opening).
double number_at(const Json& j, const char* key, const std::string& where) {
  const Json& v = at(j, key, where);
  if (!v.is_number()) throw Malformed(name_of(where, key) + " must be a number, not " + describe(v));
  return v.get<double>();
}

// An integer in [lo, hi]: 1.5, 1e30, 2.0 or "1" are refused, never cast.
int int_at(const Json& j, const char* key, const std::string& where, long long lo, long long hi) {
  const Json& v = at(j, key, where);
  // nlohmann stores non-negative integers as unsigned: compare those without a signed cast.
  bool in_range = false;
  if (v.is_number_unsigned()) {
    const auto u = v.get<unsigned long long>();
    in_range =
        u <= static_cast<unsigned long long>(hi) && (lo <= 0 || u >= static_cast<unsigned long long>(lo));
  } else if (v.is_number_integer()) {
    in_range = v.get<long long>() >= lo && v.get<long long>() <= hi;
  }
  if (!in_range) {
    throw Malformed(name_of(where, key) + " must be an integer in [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "], not " + describe(v));
  }
  return static_cast<int>(v.get<long long>());
}

std::string string_at(const Json& j, const char* key, const std::string& where) {
  const Json& v = at(j, key, where);
  if (!v.is_string()) throw Malformed(name_of(where, key) + " must be a string, not " + describe(v));
  return v.get<std::string>();
}

bool bool_at(const Json& j, const char* key, const std::string& where) {
  const Json& v = at(j, key, where);
  if (!v.is_boolean()) throw Malformed(name_of(where, key) + " must be true or false, not " + describe(v));
  return v.get<bool>();
}

// A model (or class) name: null = "" when `nullable`, else a name by is_model_name.
std::string name_at(const Json& j, const char* key, const std::string& where, bool nullable) {
  const Json& v = at(j, key, where);
  if (nullable && v.is_null()) return "";
  if (!v.is_string() || !is_model_name(v.get<std::string>())) {
    throw Malformed(name_of(where, key) +
                    " must be a model name (a file stem: no '/', not . or .., no control characters), not " +
                    describe(v));
  }
  return v.get<std::string>();
}

// A rigid transform as canopy's writers write it: 16 numbers, row-major, the last row 0 0 0 1,
// the 3 x 3 part a rotation (orthonormal within 1e-6, determinant +1).
Pose pose_from(const Json& j, const std::string& where) {
  if (!j.is_object()) throw Malformed(where + " must be an object, not " + describe(j));
  const Json& m = at(j, "matrix", where);
  if (!m.is_array() || m.size() != 16) throw Malformed(where + ".matrix must be 16 numbers");
  std::array<double, 16> a{};
  for (std::size_t i = 0; i < 16; ++i) {
    if (!m[i].is_number()) throw Malformed(where + ".matrix must be 16 numbers, not " + describe(m[i]));
    a[i] = m[i].get<double>();
  }
  members::check_rigid(a, where + ".matrix");
  Pose p;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) p.rotation[3 * r + c] = a[4 * r + c];
    p.translation[r] = a[4 * r + 3];
  }
  return p;
}

std::optional<Pose> optional_pose_from(const Json& j, const char* key, const std::string& where) {
  const Json& v = at(j, key, where);
  if (v.is_null()) return std::nullopt;
  return pose_from(v, name_of(where, key));
}

Json optional_pose(const std::optional<Pose>& p) { return p ? pose_json(*p) : Json(nullptr); }

Json hypothesis_json(const Hypothesis& h, bool has_classes) {
  Json j{{"model", h.model},
         {"gmatch_rank", h.gmatch_rank},
         {"gmatch_score", finite(h.gmatch_score, "gmatch_score")},
         {"start", h.start},
         {"flipped", h.flipped},
         {"pose", pose_json(h.pose)},
         {"pose_tile", optional_pose(h.pose_tile)},
         {"fit_rms", finite(h.fit_rms, "fit_rms")},
         {"explained", finite(h.explained, "explained")},
         {"free_space_violation", finite(h.free_space_violation, "free_space_violation")},
         {"score", finite(h.score, "score")},
         {"flip_score", finite(h.flip_score, "flip_score")}};
  if (h.tilted) j["tilted"] = true;
  if (has_classes) j["class"] = h.vehicle_class.empty() ? Json(nullptr) : Json(h.vehicle_class);
  return j;
}

Hypothesis hypothesis_from(const Json& j, const std::string& w) {
  if (!j.is_object()) throw Malformed(w + " must be an object, not " + describe(j));
  Hypothesis h;
  h.model = name_at(j, "model", w, false);
  h.gmatch_rank = int_at(j, "gmatch_rank", w, 1, std::numeric_limits<int>::max());
  h.gmatch_score = number_at(j, "gmatch_score", w);
  h.start = string_at(j, "start", w);
  h.flipped = bool_at(j, "flipped", w);
  h.pose = pose_from(at(j, "pose", w), w + ".pose");
  h.pose_tile = optional_pose_from(j, "pose_tile", w);
  h.fit_rms = number_at(j, "fit_rms", w);
  h.explained = number_at(j, "explained", w);
  h.free_space_violation = number_at(j, "free_space_violation", w);
  h.score = number_at(j, "score", w);
  h.flip_score = number_at(j, "flip_score", w);
  if (j.contains("tilted")) h.tilted = bool_at(j, "tilted", w);
  if (j.contains("class")) h.vehicle_class = name_at(j, "class", w, true);
  return h;
}

// classify's members of a class-level answer (docs/decisions/classify.md §9), each optional.
void class_keys_from(const Json& j, Verdict& v) {
  auto optional_name = [&](const char* key) { return j.contains(key) ? name_at(j, key, "", true) : ""; };
  v.level = optional_name("level");
  v.group = optional_name("group");
  v.reason = optional_name("reason");
  v.refused_on = optional_name("refused_on");
  if (!v.refused_on.empty() && v.refused_on != "density" && v.refused_on != "surface" &&
      v.refused_on != "size" && v.refused_on != "shape")
    throw Malformed("refused_on must be density, surface, size, shape or null, not \"" + v.refused_on + "\"");
  if (j.contains("detail") && !j["detail"].is_null()) v.detail = string_at(j, "detail", "");
  auto optional_number = [&](const Json& o, const char* key, const std::string& where) -> std::optional<double> {
    if (!o.contains(key) || o[key].is_null()) return std::nullopt;
    return number_at(o, key, where);
  };
  v.density = optional_number(j, "density", "");
  if (j.contains("density_needed") && !j["density_needed"].is_null()) {
    const Json& d = j["density_needed"];
    if (!d.is_object()) throw Malformed("density_needed must be an object or null, not " + describe(d));
    v.density_class = optional_number(d, "class", "density_needed");
    v.density_model = optional_number(d, "model", "density_needed");
  }
  v.heading_ambiguity = optional_number(j, "heading_ambiguity_deg", "");
  if (j.contains("size") && !j["size"].is_null()) {
    const Json& sz = j["size"];
    if (!sz.is_array() || sz.size() != 3)
      throw Malformed("size must be [L, W, H] or null, not " + describe(sz));
    std::array<double, 3> lwh{};
    for (std::size_t k = 0; k < 3; ++k) {
      if (!sz[k].is_number() || !(sz[k].get<double>() >= 0))
        throw Malformed("size must be three numbers >= 0, not " + describe(sz[k]));
      lwh[k] = sz[k].get<double>();
    }
    v.size = lwh;
  }
  if (j.contains("measured") && !j["measured"].is_null()) {
    const Json& m = j["measured"];
    if (!m.is_object()) throw Malformed("measured must be an object or null, not " + describe(m));
    // measured.<key>: n numbers (>= 0 where non_negative).
    auto numbers = [&](const char* key, std::size_t n, bool non_negative) {
      const std::string w = std::string("measured.") + key;
      const Json* a = m.contains(key) ? &m[key] : nullptr;
      if (!a || !a->is_array() || a->size() != n)
        throw Malformed(w + " must be " + std::to_string(n) + " numbers");
      std::array<double, 3> out{};
      for (std::size_t k = 0; k < n; ++k) {
        const Json& x = (*a)[k];
        if (!x.is_number() || !std::isfinite(x.get<double>()) || (non_negative && !(x.get<double>() >= 0)))
          throw Malformed(w + " must be finite numbers" + (non_negative ? " >= 0" : "") + ", not " +
                          describe(x));
        out[k] = x.get<double>();
      }
      return out;
    };
    v.measured_size = numbers("size", 3, true);
    const auto c = numbers("centre", 2, false);
    v.measured_centre = std::array<double, 2>{c[0], c[1]};
    v.measured_heading = number_at(m, "heading_deg", "measured");
    v.measured_edge_correction = optional_number(m, "edge_correction", "measured").value_or(0);
    if (!(v.measured_edge_correction >= 0) || !std::isfinite(v.measured_edge_correction))
      throw Malformed("measured.edge_correction must be a finite number >= 0");
  }
}

}  // namespace

std::string serialize_verdict(const Verdict& v) {
  const Json provenance = provenance_json(v.provenance);
  Json hyps = Json::array();
  for (const auto& h : v.hypotheses) hyps.push_back(hypothesis_json(h, v.has_classes));
  if (v.chosen >= static_cast<int>(v.hypotheses.size())) {
    throw common::Error("verdict: chosen hypothesis index out of range");
  }
  const Hypothesis* c = v.chosen >= 0 ? &v.hypotheses[v.chosen] : nullptr;
  Json j{{"format", kFormat},
         {"version", kVersion},
         {"provenance", provenance},
         {"candidate", v.candidate},
         {"model", c ? Json(c->model) : Json(nullptr)},
         {"confidence", finite(v.confidence, "confidence")},
         {"pose", c ? pose_json(c->pose) : Json(nullptr)},
         {"pose_tile", c ? optional_pose(c->pose_tile) : Json(nullptr)},
         {"fit_rms", c ? Json(c->fit_rms) : Json(nullptr)},
         {"explained", c ? Json(c->explained) : Json(nullptr)},
         {"free_space_violation", c ? Json(c->free_space_violation) : Json(nullptr)},
         {"transform", optional_pose(v.transform)},
         {"chosen", v.chosen},
         {"hypotheses", hyps}};
  if (v.has_classes) {
    auto text = [](const std::string& s) { return s.empty() ? Json(nullptr) : Json(s); };
    j["class"] = text(v.vehicle_class);
    j["nearest_instance"] = text(v.nearest_instance);
    j["class_score"] = finite(v.class_score, "class_score");
    j["class_margin"] = finite(v.class_margin, "class_margin");
  }
  if (v.box) {
    j["box"] = Json{{"explained", finite(v.box->explained, "box.explained")},
                    {"free_space_violation", finite(v.box->free_space_violation, "box.free_space_violation")},
                    {"score", finite(v.box->score, "box.score")}};
  }
  return j.dump(1) + "\n";
}

Verdict parse_verdict(const std::string& text, const std::string& name) {
  const Json j = open_json_document(text, name, kFormat);
  Verdict v;
  try {
    const Json& p = at(j, "provenance", "");
    if (!p.is_object()) throw Malformed("provenance must be an object, not " + describe(p));
    v.provenance.tool = string_at(p, "tool", "provenance");
    v.provenance.version = string_at(p, "version", "provenance");
    const Json& parameters = at(p, "parameters", "provenance");
    if (!parameters.is_object()) throw Malformed("provenance.parameters must be an object");
    for (const auto& [k, val] : parameters.items()) {
      if (!val.is_string())
        throw Malformed("provenance.parameters." + k + " must be a string, not " + describe(val));
      v.provenance.parameters.emplace_back(k, val.get<std::string>());
    }
    const Json& inputs = at(p, "inputs", "provenance");
    if (!inputs.is_array()) throw Malformed("provenance.inputs must be an array of strings");
    for (const auto& in : inputs) {
      if (!in.is_string())
        throw Malformed("provenance.inputs must be an array of strings, not " + describe(in));
      v.provenance.inputs.push_back(in.get<std::string>());
    }
    v.candidate = string_at(j, "candidate", "");
    if (v.candidate.empty()) throw Malformed("candidate must name the candidate's points (verify --points)");
    v.model = name_at(j, "model", "", true);
    v.confidence = number_at(j, "confidence", "");
    if (!(v.confidence >= 0 && v.confidence <= 1)) throw Malformed("confidence outside [0, 1]");
    v.transform = optional_pose_from(j, "transform", "");
    v.pose = optional_pose_from(j, "pose", "");
    v.pose_tile = optional_pose_from(j, "pose_tile", "");
    const Json& hyps = at(j, "hypotheses", "");
    if (!hyps.is_array()) throw Malformed("hypotheses must be an array, not " + describe(hyps));
    for (std::size_t i = 0; i < hyps.size(); ++i) {
      v.hypotheses.push_back(hypothesis_from(hyps[i], "hypotheses[" + std::to_string(i) + "]"));
    }
    v.chosen = int_at(j, "chosen", "", -1, std::numeric_limits<int>::max());
    if (j.contains("class")) {
      v.has_classes = true;
      v.vehicle_class = name_at(j, "class", "", true);
      v.nearest_instance = name_at(j, "nearest_instance", "", true);
      v.class_score = number_at(j, "class_score", "");
      v.class_margin = number_at(j, "class_margin", "");
    }
    if (j.contains("box")) {
      const Json& b = at(j, "box", "");
      if (!b.is_object()) throw Malformed("box must be an object, not " + describe(b));
      Verdict::Box box;
      box.explained = number_at(b, "explained", "box");
      box.free_space_violation = number_at(b, "free_space_violation", "box");
      box.score = number_at(b, "score", "box");
      v.box = box;
    }
    if (v.chosen >= static_cast<int>(v.hypotheses.size())) {
      throw Malformed("chosen is not -1 or a hypothesis index");
    }
    if ((v.chosen >= 0) != !v.model.empty() || (v.chosen >= 0 && v.hypotheses[v.chosen].model != v.model)) {
      throw Malformed("model and chosen disagree");
    }
    class_keys_from(j, v);
    if (!v.model.empty() && !v.pose && !v.pose_tile) throw Malformed("a model without a pose");
    if (v.model.empty() && !v.vehicle_class.empty() && v.level == "class" && !v.pose && !v.pose_tile) {
      throw Malformed("a class without a pose");
    }
  } catch (const Malformed& e) { throw DataError(name, std::string("malformed verdict: ") + e.what()); }
  return v;
}

bool is_model_name(const std::string& name) {
  if (name.empty() || name.size() > 255 || name == "." || name == "..") return false;
  for (const unsigned char c : name) {
    if (c == '/' || c < 0x20 || c == 0x7f) return false;
  }
  return true;
}

Verdict read_verdict(const std::string& path) { return parse_verdict(common::read_file(path), path); }

void write_verdict(const Verdict& verdict, const std::string& path) {
  common::write_file_atomic(path, serialize_verdict(verdict));
}

}  // namespace canopy::documents
