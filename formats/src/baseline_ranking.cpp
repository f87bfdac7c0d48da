#include "canopy/formats/baseline_ranking.h"

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"

namespace canopy::formats {

std::vector<BaselineMethod> parse_baseline_ranking(const std::string& text, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) { throw common::DataError(name, std::string("not JSON: ") + e.what()); }
  if (!j.is_object() || j.value("format", "") != "canopy.baseline")
    throw common::DataError(name, "not a canopy.baseline document");
  std::vector<BaselineMethod> out;
  try {
    for (const auto& m : j.at("methods")) {
      BaselineMethod bm;
      bm.method = m.at("method").get<std::string>();
      for (const auto& e : m.at("models")) {
        BaselineModel x{e.at("model").get<std::string>(), std::nullopt};
        if (e.contains("score")) x.score = e.at("score").get<double>();
        bm.models.push_back(x);
      }
      out.push_back(std::move(bm));
    }
  } catch (const nlohmann::json::exception& e) {
    throw common::DataError(name, std::string("malformed canopy.baseline: ") + e.what());
  }
  return out;
}

}  // namespace canopy::formats
