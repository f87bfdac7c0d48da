// The experiment's manifest: where make put every artifact the report reads, so that `report`
// spells no path of make's layout (Makefile.experiments writes $(OUT)/experiment.txt at parse
// time, when its text changed; `report --manifest` reads it). Text, one record a line, blanks
// between fields (no path holds one), '#' starts a comment, blank lines skipped:
//
//   trial OBJECT SCENE NOISE_MM DIR           a thesis-protocol trial; DIR holds its stages'
//                                             outputs by their names (scan.pcd, samples.pcd,
//                                             mesh.ply, segments.json, match.json, verdict.json,
//                                             areas.json, baseline.json) and their .time files
//   model OBJECT GRAPH                        the modelbase entry's segment graph
//   render OBJECT SCENE SCAN                  the noise-free rendering (SCAN.time: its time;
//                                             SCAN itself, while it exists: its views)
//   ablation NAME CHANGE                      a variant; CHANGE is the stage and its options,
//                                             '+' for each blank ("ncut+--exponent+squared")
//   ablation-trial NAME OBJECT SCENE NOISE_MM MATCH   the variant's match.json for a trial
//   figure PATH                               a figure the report links (relative to its
//                                             results directory), in the report's order
//   real NAME DIR [TRUTH]                     a real tile's workflow directory (mk/real.mk) and
//                                             its hand labels when it has any
//   real-ablation NAME DIR CONFIG             the same tile's workflow run again with classify's
//                                             parameters CONFIG (an ablation: mk/real.mk
//                                             REAL_CLASSIFY_ABLATIONS: one record per entry,
//                                             in the list's order, each in its own DIR)
//                                             into DIR; after its real
//   density LEVEL SPACING SCORE [ABLATION_CONFIG ABLATION_SCORE]
//                                             a rung of the density ladder (mk/density.mk):
//                                             its nominal points/m² (a positive number), the
//                                             renderer's pixel spacing in m, its score.json;
//                                             and, when classify's ablation runs on the rung,
//                                             the ablation's parameter file and its score.json
//   density-sensor LEVEL PRESET SCORE [ABLATION_CONFIG ABLATION_SCORE]
//                                             a rung of the ladder on the realistic sensor
//                                             (mk/density.mk): its nominal pulses/m² (a
//                                             positive number, rising), the sensor preset
//                                             (share/sensors/<PRESET>.ini; one preset for
//                                             every such record), its score.json; and, when
//                                             classify's ablation runs on the rung, the
//                                             ablation's parameter file and its score.json
//   density-verify LADDER LEVEL CHANGE SCORE  verify's ablation on a rung (after the rung's
//                                             record): LADDER `pixel` (a density record) or the
//                                             sensor preset (density-sensor), the rung's level,
//                                             verify's options ('+' for each blank), the
//                                             ablation's score.json
//   density-classify LADDER LEVEL CONFIG SCORE
//                                             classify's second (third, ...) ablation on a
//                                             rung, one record each in that order (after the
//                                             rung's record, before or after its density-verify;
//                                             no score twice on a rung): LADDER and LEVEL as for
//                                             density-verify, the ablation's parameter file and
//                                             its score.json
//   density-detect LADDER LEVEL CONFIG SCORE  detect's first (second, ...) ablation on a rung,
//                                             one record each in that order (after the rung's
//                                             record, among its other ablations' records; no
//                                             score twice on a rung): LADDER and LEVEL as for
//                                             density-verify, detect's parameter file and the
//                                             score.json of the rung's chain run again with it
//
// The trials are a full grid: every (object, scene, noise) of the trial lines exactly once
// (objects, scenes and noises in the order they first appear), and every ablation has a trial
// for each of them. OBJECT, SCENE and NAME are words of letters, digits, '-', '_' and '.'.
// Every refusal is a common::DataError naming the file and the line.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace canopy::documents {

struct ManifestTrial {
  std::string object, scene;
  int noise_mm = 0;
  std::string path;  // trial: its directory; ablation-trial: its match.json
};

struct ManifestAblation {
  std::string name, change;           // change with blanks ('+' undone)
  std::vector<ManifestTrial> trials;  // in the manifest's order
};

// A real tile run again with other classify parameters (real-ablation): its directory and the
// parameter file.
struct ManifestRealAblation {
  std::string dir, config;
};

struct ManifestRealTile {
  std::string name, dir, truth;                   // truth "" = no labels (no vehicles on the tile)
  std::vector<ManifestRealAblation> ablations{};  // classify's ablations, in the manifest's order
};

// One ablation of a density rung: what it changes (classify's or detect's parameter file, or
// verify's options with blanks restored) and its score.json; both "" = none.
struct ManifestRungAblation {
  std::string change{}, score{};
};

struct ManifestDensity {
  double level = 0;                 // nominal points per m² (a sensor rung: pulses per m²)
  double spacing = 0;               // pixel spacing, m (0 for a sensor rung)
  std::string score;                // canopy.scene_score of the rung's tiles
  std::string sensor;               // the sensor preset of a density-sensor rung; "" for the pixel ladder
  ManifestRungAblation classify{};  // classify's ablation (the density record's last two words)
  ManifestRungAblation verify{};    // verify's ablation (density-verify)
  // classify's second, third, ... ablations (density-classify records, in their order: the
  // entries after the first of mk/density.mk's DENSITY_[SENSOR_]CLASSIFY_ABLATIONS).
  std::vector<ManifestRungAblation> classify_more{};
  // detect's ablations (density-detect records, in their order: mk/density.mk's
  // DENSITY_[SENSOR_]DETECT_ABLATIONS on the class-level rungs), each the rung's whole chain again.
  std::vector<ManifestRungAblation> detect{};
};

struct ExperimentManifest {
  std::vector<std::string> objects, scenes;  // of the trials, in order of first appearance
  std::vector<int> noises;
  std::vector<ManifestTrial> trials;            // in the manifest's order
  std::map<std::string, std::string> models;    // object -> segment graph
  std::map<std::string, std::string> renders;   // "<object>/<scene>" -> scan
  std::vector<ManifestAblation> ablations;      // in order of declaration
  std::vector<std::string> figures;             // in order
  std::vector<ManifestRealTile> real;           // in order
  std::vector<ManifestDensity> density;         // in order (rising level)
  std::vector<ManifestDensity> density_sensor;  // the sensor ladder, in order (rising level)

  // The directory of trial (object, scene, noise); "" when there is none.
  std::string trial_dir(const std::string& object, const std::string& scene, int noise_mm) const;
};

// At most this many records (a manifest beyond it is refused).
inline constexpr std::size_t kMaxManifestRecords = 1000000;

// The manifest in `text` (of file `name`): at least one trial.
ExperimentManifest parse_experiment_manifest(const std::string& text, const std::string& name);
ExperimentManifest read_experiment_manifest(const std::string& path);
// Its text (the tests write manifests with it; make writes the same records).
std::string write_experiment_manifest(const ExperimentManifest& m);

}  // namespace canopy::documents
