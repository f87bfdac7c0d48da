// Reading the footprints topview draws from the detections, truth and score documents.
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "topview/topview.h"

namespace canopy::topview {
namespace {

using Json = nlohmann::json;

Json read_json(const std::string& path, const char* format) {
  Json j;
  try {
    j = Json::parse(common::read_file(path));
  } catch (const Json::parse_error& e) {
    throw common::DataError(path, std::string("not JSON: ") + e.what());
  }
  if (!j.is_object() || !j.contains("format") || j["format"] != format) {
    throw common::DataError(path, std::string("not a ") + format + " document");
  }
  return j;
}

Ring ring_of(const Json& fp, const std::string& path, const std::string& where) {
  Ring r;
  if (!fp.is_array() || fp.size() < 3 || fp.size() > 64)
    throw common::DataError(path, where + ": not a footprint polygon");
  for (const auto& p : fp) {
    if (!p.is_array() || p.size() < 2 || !p[0].is_number() || !p[1].is_number()) {
      throw common::DataError(path, where + ": a corner is not [x, y]");
    }
    r.push_back({p[0].get<double>(), p[1].get<double>()});
  }
  return r;
}

// The score's matches of this tile: the outcome of each candidate (right, wrong,
// false_alarm) and the missed vehicles' instances.
struct Outcomes {
  std::map<std::string, std::string> of_candidate;
  std::set<long long> missed;
};

Outcomes read_outcomes(const std::string& path, int tile) {
  Outcomes o;
  const Json s = read_json(path, "canopy.scene_score");
  if (!s.contains("tiles") || !s["tiles"].is_array() || tile >= static_cast<int>(s["tiles"].size())) {
    throw common::DataError(path, "has no tile " + std::to_string(tile));
  }
  for (const auto& m : s.value("matches", Json::array())) {
    if (m.value("tile", -1) != tile) continue;
    if (m["outcome"] == "missed") {
      o.missed.insert(m["instance"].get<long long>());
    } else {
      o.of_candidate[m["candidate"].get<std::string>()] = m["outcome"].get<std::string>();
    }
  }
  return o;
}

Rgb detection_colour(const Outcomes& o, const Json& detection) {
  const auto it = o.of_candidate.find(detection.value("candidate", std::string()));
  return it == o.of_candidate.end() ? kDetection
         : it->second == "right"    ? kRight
         : it->second == "wrong"    ? kWrong
                                    : kFalseAlarm;
}

}  // namespace

std::vector<Shape> read_footprints(const Sources& sources, int tile) {
  const Json d = read_json(sources.detections, "canopy.detections");
  const bool scored = !sources.score.empty();
  const Outcomes outcomes = scored ? read_outcomes(sources.score, tile) : Outcomes{};
  std::vector<Shape> shapes;
  if (!sources.truth.empty()) {
    const Json t = read_json(sources.truth, "canopy.scene_truth");
    std::size_t k = 0;
    for (const auto& v : t.value("vehicles", Json::array())) {
      const std::string where = "vehicles[" + std::to_string(k++) + "]";
      const bool miss = outcomes.missed.count(v.value("instance", -1LL)) > 0;
      shapes.push_back({ring_of(v.value("footprint", Json()), sources.truth, where), miss ? kMissed : kTruth});
    }
  }
  std::size_t k = 0;
  for (const auto& det : d.value("detections", Json::array())) {
    const std::string where = "detections[" + std::to_string(k++) + "]";
    const Rgb c = scored ? detection_colour(outcomes, det) : kDetection;
    shapes.push_back({ring_of(det.value("footprint", Json()), sources.detections, where), c});
  }
  return shapes;
}

}  // namespace canopy::topview
