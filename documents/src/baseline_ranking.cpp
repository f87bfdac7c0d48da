#include "canopy/documents/baseline_ranking.h"

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/formats/json_fields.h"

namespace canopy::documents {

std::vector<BaselineMethod> parse_baseline_ranking(const std::string& text, const std::string& name) {
  nlohmann::ordered_json j;
  try {
    j = nlohmann::ordered_json::parse(text);
  } catch (const std::exception& e) { throw common::DataError(name, std::string("not JSON: ") + e.what()); }
  if (!j.is_object() || !j.contains("format") || j["format"] != kBaselineRankingFormat)
    throw common::DataError(name, "not a canopy.baseline document");
  if (j.contains("version") && j["version"] != kBaselineRankingVersion) {
    throw common::DataError(name, "canopy.baseline version " + formats::json_describe(j["version"]) +
                                      " is not supported (this build reads version 1)");
  }
  std::vector<BaselineMethod> out;
  try {
    for (const auto& m : j.at("methods")) {
      BaselineMethod bm;
      bm.method = m.at("method").get<std::string>();
      for (const auto& e : m.at("models")) {
        BaselineModel x;
        x.model = e.at("model").get<std::string>();
        if (e.contains("score")) x.score = e.at("score").get<double>();
        bm.models.push_back(x);
      }
      out.push_back(std::move(bm));
    }
  } catch (const nlohmann::ordered_json::exception& e) {
    throw common::DataError(name, std::string("malformed canopy.baseline: ") + e.what());
  }
  return out;
}

std::string serialize_baseline_ranking(const BaselineRanking& ranking) {
  using Json = nlohmann::ordered_json;
  Json methods = Json::array();
  for (const auto& m : ranking.methods) {
    Json models = Json::array();
    for (const auto& e : m.models) {
      if (!e.score) throw common::Error("refusing to write baseline model " + e.model + " without a score");
      Json j{{"rank", e.rank}, {"model", e.model}, {"score", *e.score}};
      if (m.method == "vfh") {
        j["distance"] = e.distance;
        j["view"] = e.view;
      } else {
        j["fitness"] = e.fitness;
        j["candidate_share"] = e.candidate_share;
        j["model_share"] = e.model_share;
        j["pose"] = e.pose ? Json(*e.pose) : Json(nullptr);
      }
      models.push_back(j);
    }
    methods.push_back(Json{{"method", m.method}, {"models", models}});
  }
  const Json j{{"format", kBaselineRankingFormat},
               {"version", kBaselineRankingVersion},
               {"provenance", formats::provenance_json(ranking.provenance)},
               {"object", ranking.object},
               {"candidate_points", ranking.candidate_points},
               {"methods", methods}};
  return formats::json_document_text(j);
}

}  // namespace canopy::documents
