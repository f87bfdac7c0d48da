// The ranking document of `baseline` (JSON format "canopy.baseline", version 1,
// formats/README.md): per method, every model best first. `baseline` writes it; report's
// thesis table and famscore's class tables read it.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/provenance.h"

namespace canopy::documents {

constexpr const char* kBaselineRankingFormat = "canopy.baseline";
constexpr int kBaselineRankingVersion = 1;  // the only version written

struct BaselineModel {
  std::string model;
  // In [0, 1], larger is better; FPFH: 0 = RANSAC found no pose. The writer needs it; absent,
  // the reader leaves it to the caller (report's table needs only the order).
  std::optional<double> score;
  // Written, not read (no reader uses them): the rank (1 = the method's answer), and per method
  // vfh: distance (L1 of the normalised histograms, in [0, 2]) and view (the nearest view's
  // index); fpfh: fitness, the two shares and the pose (model -> candidate, row-major 4 x 4;
  // none = RANSAC found no pose).
  int rank = 0;
  double distance = 0;
  int view = -1;
  double fitness = 0, candidate_share = 0, model_share = 0;
  std::optional<std::array<double, 16>> pose;
};

struct BaselineMethod {
  std::string method;                 // "vfh", "fpfh"
  std::vector<BaselineModel> models;  // as written: rank 1 first
};

struct BaselineRanking {
  formats::Provenance provenance;
  std::string object;  // the candidate, as given
  int candidate_points = 0;
  std::vector<BaselineMethod> methods;
};

// Reads the methods and, per model, its name and score (what the readers use). Throws
// common::DataError naming `name`: "not JSON: ...", "not a canopy.baseline document",
// "malformed canopy.baseline: ..." (a method or model without its keys).
std::vector<BaselineMethod> parse_baseline_ranking(const std::string& text, const std::string& name);

// The document as `baseline` writes it: vfh models with distance and view, others with
// fitness, shares and pose (null without one). No times: same inputs, same bytes. A model
// without a score is a common::Error.
std::string serialize_baseline_ranking(const BaselineRanking& ranking);

}  // namespace canopy::documents
