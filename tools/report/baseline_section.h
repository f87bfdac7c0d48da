// The PCL baseline beside canopy (issue 17): rank-1 per object, per noise level and per scene of the
// baseline's two methods (tools/baseline: VFH nearest view, FPFH + RANSAC + ICP) next to
// gmatch's, from each trial's baseline.json (mk/baseline.mk), with the baseline's time.
#pragma once

#include <string>
#include <vector>

#include "canopy/documents/experiment_manifest.h"

namespace canopy::report {

struct BaselineSection {
  std::string markdown;  // empty when no trial has a baseline.json
  std::string csv;       // results/baseline.csv: one row per trial with a baseline.json
};

// Reads each trial's {baseline.json, baseline.json.time, match.json, verdict.json} in the
// directory the manifest names, in the grid's order (objects x scenes x noises).
// Trials without baseline.json are left out (and counted in the text); an empty baseline.json
// (a failed run recorded by stagerun --record-failure) counts as wrong for both methods.
BaselineSection baseline_section(const documents::ExperimentManifest& manifest);

}  // namespace canopy::report
