// The ground truth of a tile's candidates: candidate_truth.json, format
// "canopy.candidate_truth", version 1 (formats/README.md "Candidate truth"). candtruth writes it
// from a labelled tile and detect's index (issue 30: the truth lives outside the recogniser's
// path; detect's index and crops hold none). Nothing in the experiment reads it; people and the
// tests do.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "canopy/formats/provenance.h"

namespace canopy::documents {

inline constexpr const char* kCandidateTruthFormat = "canopy.candidate_truth";
inline constexpr int kCandidateTruthVersion = 1;

// One candidate of the index, in the index's order.
struct CandidateTruthRow {
  std::string id;                // the index's candidate id
  std::int64_t crop_points = 0;  // tile points inside the candidate's crop box
  std::int64_t instance = 0;     // the vehicle with the most points in the crop; 0 = none (a false candidate)
  std::int64_t points = 0;       // that vehicle's points in the crop
  double coverage = 0;           // ... as a share of the vehicle's points in the tile
  double purity = 0;             // ... as a share of the crop's points that are not ground
};

// A labelled vehicle of the tile and the candidates whose truth it is.
struct InstanceTruthRow {
  std::int64_t instance = 0;
  std::int64_t points = 0;              // its points in the tile
  std::vector<std::string> candidates;  // ids, in the index's order
};

struct CandidateTruth {
  std::string tile, index;  // the files read, as given
  std::vector<CandidateTruthRow> candidates;
  std::vector<InstanceTruthRow> instances;  // ascending instance id
};

// The text as candtruth writes it (one space indent, a final newline; provenance from `prov`).
// Throws common::Error for a non-finite number (a writer's bug).
std::string write_candidate_truth(const CandidateTruth& t, const formats::Provenance& prov);

// Reads `text`, the contents of file `name`. Throws common::DataError naming `name`: not JSON,
// another format or version, a member missing or of a wrong type, a count not an integer in
// [0, 2^53], a share outside [0, 1], an instance's candidate id that is not a candidate's.
CandidateTruth read_candidate_truth(const std::string& text, const std::string& name);
CandidateTruth read_candidate_truth_file(const std::string& path);

}  // namespace canopy::documents
