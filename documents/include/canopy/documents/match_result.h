// The match result (JSON format "canopy.match_result", version 1, formats/README.md): gmatch writes
// it; verify, report and famscore read it. Every model's score and error terms, ranked, with its
// segment pairs.
// Readers check "format" and "version", every integer's type and range, that numbers are
// finite, and name the file and the key in every error.
#pragma once

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
};

struct MatchResult {
  formats::Provenance provenance;
  std::string object;              // object segment graph path, as given
  std::string error_form;          // "bounded" or "thesis"
  std::vector<ModelScore> models;  // sorted by rank
  double entropy = 0;              // bits
};

// Score of the rank-1 model minus that of the rank-2 model (the "margin" key of the file,
// null there when fewer than two models); NaN when fewer than two models.
double match_margin(const MatchResult& result);

MatchResult read_match_result(const std::string& path);
MatchResult parse_match_result(const std::string& text, const std::string& name);
void write_match_result(const MatchResult& result, const std::string& path);
std::string serialize_match_result(const MatchResult& result);

}  // namespace canopy::documents
