// Reading the ranking document of `baseline` (JSON format "canopy.baseline", version 1,
// formats/README.md): per method, every model best first. Only what its readers use (report's
// thesis table, famscore's class tables); `baseline` itself writes the whole document.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace canopy::formats {

struct BaselineModel {
  std::string model;
  // In [0, 1], larger is better; FPFH: 0 = RANSAC found no pose. `baseline` always writes it;
  // absent, the reader leaves it to the caller (report's table needs only the order).
  std::optional<double> score;
};

struct BaselineMethod {
  std::string method;                 // "vfh", "fpfh"
  std::vector<BaselineModel> models;  // as written: rank 1 first
};

// Throws common::DataError naming `name`: "not JSON: ...", "not a canopy.baseline document",
// "malformed canopy.baseline: ..." (a method or model without its keys).
std::vector<BaselineMethod> parse_baseline_ranking(const std::string& text, const std::string& name);

}  // namespace canopy::formats
