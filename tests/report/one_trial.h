// The smallest experiment manifest the report binary accepts, for the tests that run it: one
// thesis trial (the report needs one) with its match and segments.
#pragma once

#include <filesystem>

#include "canopy/documents/experiment_manifest.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/segment_graph.h"

namespace canopy::report::testing {

// Writes DIR/out/sedan/circle/noise-0/{match.json (sedan at rank 1, 0.8), segments.json (empty)}
// and returns a manifest holding that trial; the caller adds its records and writes it.
inline documents::ExperimentManifest one_trial_manifest(const std::filesystem::path& dir) {
  const std::filesystem::path trial = dir / "out" / "sedan" / "circle" / "noise-0";
  std::filesystem::create_directories(trial);
  documents::MatchResult m;
  m.error_form = "bounded";
  documents::ModelScore top;
  top.model = "sedan";
  top.rank = 1;
  top.score = 0.8;
  m.models.push_back(top);
  documents::write_match_result(m, (trial / "match.json").string());
  documents::write_segment_graph(documents::SegmentGraph{}, (trial / "segments.json").string());
  documents::ExperimentManifest manifest;
  manifest.trials.push_back({"sedan", "circle", 0, trial.string()});
  return manifest;
}

}  // namespace canopy::report::testing
