// The match result (JSON format "canopy.match_result", version 1, formats/README.md): gmatch writes
// it; verify, report and famscore read it. Every model's score and error terms, ranked, with its
// segment pairs; `baseline --hypotheses` writes one too (the FPFH ranking, no pairs, a pose per
// model), which verify checks as it checks gmatch's.
// Readers check "format" and "version", every integer's type and range, that numbers are
// finite, and name the file and the key in every error.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/provenance.h"

namespace canopy::documents {

constexpr const char* kMatchResultFormat = "canopy.match_result";
constexpr int kMatchResultVersion = 1;  // the only version written and read

struct SegmentPair {
  int object_segment = 0;  // segment id in the object graph
  int model_segment = -1;  // segment id in the model graph; -1 = NULL match
  double unary_error = 0;
};

struct ModelScore {
  std::string model;  // model name (file stem in the modelbase)
  double score = 0;   // S = 1 - E
  int rank = 0;       // 1 = best
  double error_unary = 0, error_orientation = 0, error_distance = 0, error_coverage = 0;
  double error_total = 0;
  std::vector<SegmentPair> pairs;
  // Optional: a pose of the model in the candidate frame (model -> candidate coordinates,
  // row-major 4 x 4, rigid), verify's start instead of the pairs' pose. gmatch writes none
  // (no "pose" key); baseline --hypotheses writes its RANSAC(+ICP) pose.
  std::optional<std::array<double, 16>> pose;
};

struct MatchResult {
  formats::Provenance provenance;
  std::string object;              // as given: gmatch's segment graph; baseline's points
  std::string error_form;          // "bounded" or "thesis"
  std::vector<ModelScore> models;  // sorted by rank
  double entropy = 0;              // bits
};

// Score of the rank-1 model minus that of the rank-2 model (the "margin" key of the file,
// null there when fewer than two models); NaN when fewer than two models.
double match_margin(const MatchResult& result);

// The entropy (bits) of a ranking's scores, thesis Eq. 6.14-6.15: of the scores (negatives as 0)
// normalised to sum 1; log2(n) when none is positive, 0 for none. gmatch's and baseline's
// "entropy".
double match_entropy(const std::vector<double>& scores);

MatchResult read_match_result(const std::string& path);
MatchResult parse_match_result(const std::string& text, const std::string& name);
void write_match_result(const MatchResult& result, const std::string& path);
std::string serialize_match_result(const MatchResult& result);

}  // namespace canopy::documents
