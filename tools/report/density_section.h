// The report's "Density ladder" section (issue 27; mk/density.mk,
// docs/decisions/density-ladder.md): the scene experiment's tiles rendered at several densities,
// each level scored like the scene experiment; per level and cover the rates with their 95%
// intervals, the measured density, the CPU per hectare, and the lowest level from which each
// capability meets its target.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "canopy/documents/experiment_manifest.h"
#include "canopy/documents/scene_score.h"

namespace canopy::report {

// One level of the ladder as read: its score (absent when the level has not run), the density
// measured by detect (mean over the level's runs of index.json density.all and density.ground,
// -1 unknown) and the CPU of its stages (scene_times) per hectare of rendered tile.
struct DensityLevel {
  double level = 0, spacing = 0;
  // The sensor ladder's levels (the manifest's density-sensor records): the preset, and the
  // pulses and returns per m² rangetrace measured (means over the level's tiles of truth.json
  // density.pulses_per_m2 and returns_per_m2; -1 unknown). "" and -1 for the pixel ladder.
  std::string sensor;
  double pulses = -1, returns = -1;
  std::string score_path;
  bool scored = false;
  documents::SceneScore score;
  double density_all = -1, density_ground = -1;
  int density_runs = 0;
  double cpu_seconds = 0, area_ha = 0;
  // The candidates' fate over the level's runs (detections.json by_reason; "found" = answered
  // as a vehicle at either level) and, per true model, vehicles found at either level / true
  // (score's matches: right or wrong = found).
  std::map<std::string, int> by_reason;
  std::map<std::string, std::pair<int, int>> model_found;
  // The vehicles missed at both levels by score's fate (report::fate_label; vehicle-runs over the
  // noise levels, as model_found).
  std::map<std::string, int> missed_by_fate;
  // The rung's ablations on the same candidates (documents::ManifestRungAblation): what each
  // changes, and its score when it has run.
  struct Ablation {
    std::string change;  // classify: its parameter file; verify: its options
    bool scored = false;
    documents::SceneScore score;
  };
  Ablation classify;                    // the manifest's density or density-sensor ablation
  Ablation verify;                      // density-verify, on the model-level candidates
  std::vector<Ablation> classify_more;  // density-classify: classify's second, third, ... ablations
  std::vector<Ablation> detect;         // density-detect: detect's ablations (the rung's chain again)
};

// Reads each level's score.json and its runs' index.json and .time files (a missing score is a
// level not run; a malformed document throws common::DataError naming it).
std::vector<DensityLevel> read_density_levels(const std::vector<documents::ManifestDensity>& levels);

// The capabilities' targets (issue 27) and the level from which each is met.
struct DensityTarget {
  std::string capability;  // e.g. "recall, light cover"
  std::string target;      // e.g. ">= 90%"
  // The lowest level from which the point estimate meets the target at every level above it
  // (0 = at no level); the same with the interval's conservative bound.
  double from_level = 0, from_level_bound = 0;
};
std::vector<DensityTarget> density_targets(const std::vector<DensityLevel>& levels);

// The section (Markdown; `figures`: the two pictures' paths relative to report.md, "" = none) and
// its table as CSV (level,spacing_m,density_all,density_ground,cover,metric,value,lo,hi): every
// metric (`part` all), the rates (rates: recall, precision, class right, identification) or the
// errors (errors: heading median, false alarms per ha); figures plot draws the last two
// (results/density/ladder-rates.png, ladder-errors.png: mk/density.mk).
// With `sensor` (the sensor ladder's levels, read the same way), a second part "The ladder on the
// realistic sensor (<preset>)": its own table (measured pulses and returns per m² in place of the
// spacing), per model, the candidates' fate and where each capability begins, and the two ladders
// side by side at the nominal densities both have. Where verify's ablation has run on a rung of
// either ladder, a table "verify's ablation on the density ladder" beside canopy's (the rungs
// where either has a model-level answer). Where detect's ablations have run (the class-level
// rungs), a table "detect's ablation on the density ladder" (the sensor ladder's: "... on the
// sensor ladder"; the second: "detect's second ablation ...") with classify's ablations' columns.
std::string density_markdown(const std::vector<DensityLevel>& levels, const std::vector<std::string>& figures,
                             const std::vector<DensityLevel>& sensor = {});
std::string density_csv(const std::vector<DensityLevel>& levels, const std::string& part = "all");

}  // namespace canopy::report
