#include "canopy/formats/verdict.h"

#include "canopy/formats/json_document.h"
#include "canopy/formats/provenance.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/math.h"

namespace canopy::formats {
namespace {

using common::DataError;
using Json = nlohmann::ordered_json;

constexpr const char* kFormat = "canopy.verdict";
constexpr int kVersion = 1;

double finite(double v, const char* what) {
  if (!std::isfinite(v)) throw common::Error(std::string("refusing to write non-finite ") + what);
  return v;
}

Json pose_json(const Pose& p) {
  Json m = Json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m.push_back(finite(p.rotation[3 * r + c], "pose"));
    m.push_back(finite(p.translation[r], "pose"));
  }
  for (double v : {0.0, 0.0, 0.0, 1.0}) m.push_back(v);
  const auto e = euler_degrees(p);
  return Json{{"matrix", m},
              {"translation", Json::array({p.translation[0], p.translation[1], p.translation[2]})},
              {"heading_deg", e[0]},
              {"pitch_deg", e[1]},
              {"roll_deg", e[2]}};
}

Pose pose_from(const Json& j) {
  const auto m = j.at("matrix").get<std::vector<double>>();
  if (m.size() != 16) throw std::invalid_argument("pose matrix needs 16 numbers");
  Pose p;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) p.rotation[3 * r + c] = m[4 * r + c];
    p.translation[r] = m[4 * r + 3];
  }
  for (double v : m) {
    if (!std::isfinite(v)) throw std::invalid_argument("pose matrix has a non-finite number");
  }
  return p;
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
  if (has_classes) j["class"] = h.vehicle_class.empty() ? Json(nullptr) : Json(h.vehicle_class);
  return j;
}

Hypothesis hypothesis_from(const Json& j) {
  Hypothesis h;
  h.model = j.at("model").get<std::string>();
  h.gmatch_rank = j.at("gmatch_rank").get<int>();
  h.gmatch_score = j.at("gmatch_score").get<double>();
  h.start = j.at("start").get<std::string>();
  h.flipped = j.at("flipped").get<bool>();
  h.pose = pose_from(j.at("pose"));
  if (!j.at("pose_tile").is_null()) h.pose_tile = pose_from(j.at("pose_tile"));
  h.fit_rms = j.at("fit_rms").get<double>();
  h.explained = j.at("explained").get<double>();
  h.free_space_violation = j.at("free_space_violation").get<double>();
  h.score = j.at("score").get<double>();
  h.flip_score = j.at("flip_score").get<double>();
  if (j.contains("class") && !j.at("class").is_null()) h.vehicle_class = j.at("class").get<std::string>();
  return h;
}

}  // namespace

std::array<double, 3> euler_degrees(const Pose& p) {
  const auto& R = p.rotation;
  const double deg = 180.0 / common::kPi;
  const double pitch = std::asin(std::max(-1.0, std::min(1.0, -R[6])));
  const double heading = std::atan2(R[3], R[0]);
  const double roll = std::atan2(R[7], R[8]);
  return {heading * deg, pitch * deg, roll * deg};
}

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
  return j.dump(1) + "\n";
}

Verdict parse_verdict(const std::string& text, const std::string& name) {
  const Json j = open_json_document(text, name, kFormat);
  Verdict v;
  try {
    const Json& p = j.at("provenance");
    v.provenance.tool = p.at("tool").get<std::string>();
    v.provenance.version = p.at("version").get<std::string>();
    for (const auto& [k, val] : p.at("parameters").items()) {
      v.provenance.parameters.emplace_back(k, val.get<std::string>());
    }
    v.provenance.inputs = p.at("inputs").get<std::vector<std::string>>();
    v.candidate = j.at("candidate").get<std::string>();
    v.model = j.at("model").is_null() ? "" : j.at("model").get<std::string>();
    v.confidence = j.at("confidence").get<double>();
    if (!(v.confidence >= 0 && v.confidence <= 1)) throw std::invalid_argument("confidence outside [0, 1]");
    if (!j.at("transform").is_null()) v.transform = pose_from(j.at("transform"));
    for (const auto& h : j.at("hypotheses")) v.hypotheses.push_back(hypothesis_from(h));
    v.chosen = j.at("chosen").get<int>();
    if (j.contains("class")) {
      v.has_classes = true;
      v.vehicle_class = j.at("class").is_null() ? "" : j.at("class").get<std::string>();
      v.nearest_instance =
          j.at("nearest_instance").is_null() ? "" : j.at("nearest_instance").get<std::string>();
      v.class_score = j.at("class_score").get<double>();
      v.class_margin = j.at("class_margin").get<double>();
    }
    if (v.chosen < -1 || v.chosen >= static_cast<int>(v.hypotheses.size())) {
      throw std::invalid_argument("chosen is not -1 or a hypothesis index");
    }
    if ((v.chosen >= 0) != !v.model.empty() || (v.chosen >= 0 && v.hypotheses[v.chosen].model != v.model)) {
      throw std::invalid_argument("model and chosen disagree");
    }
  } catch (const DataError&) { throw; } catch (const std::exception& e) {
    throw DataError(name, std::string("malformed verdict: ") + e.what());
  }
  return v;
}

Verdict read_verdict(const std::string& path) { return parse_verdict(common::read_file(path), path); }

void write_verdict(const Verdict& verdict, const std::string& path) {
  common::write_file_atomic(path, serialize_verdict(verdict));
}

}  // namespace canopy::formats
