// The report's "Real tiles" section (issue 26; mk/real.mk, docs/decisions/real-tiles.md): the
// tile workflow on real airborne tiles, scored against hand labels on the urban tiles and
// counted as false alarms on the forest plots.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "canopy/documents/stage_time.h"

namespace canopy::report {

// Where one tile's artifacts are: dir = out/real/<name> (tile.time, detections.json,
// cands/index.json, score.json and every stage's .time), truth = the hand labels
// (share/real/<name>.truth.json), "" for a plot without vehicles (every detection there is a
// false alarm).
struct RealTileFiles {
  std::string name, dir, truth;
};

// A count of k out of n.
struct Count {
  int k = 0, n = 0;
};

// What the section shows of one tile, read from its documents (formats::open_json_document:
// canopy.detections v1 or v2 as SCHEMA.md defines v2, canopy.candidates, canopy.scene_score,
// canopy.scene_truth) and .time files (documents::read_stage_time).
struct RealTile {
  std::string name;
  bool labelled = false;  // has hand labels (an urban test tile)
  bool ran = false;       // tile.time exists: the workflow was run
  bool finished = false;  // detections.json exists (a time-boxed run that was stopped has none)
  // A run that did not finish: the first line with "error:" of the tile's stage logs (<dir>/*.log,
  // by name), i.e. the tool that refused the tile; "" when there is none (stopped by the time box).
  std::string error;
  documents::StageTime time;  // tile.time: the whole run (sub-make and every stage under it)
  double stages_cpu = 0;      // CPU summed over the tile's stage .time files (detect … collect, score)
  int stage_runs = 0;         // those files
  long long points = -1;      // the tile's points (index tile_points), -1 unknown
  double area_ha = 0;         // the labels' extent (labelled), else the occupied ground cells' area
  std::string area_from;      // how area_ha was found
  double density = -1;        // points per m², -1 unknown
  std::string density_from;   // "index" (detect's density.all) or "measured" (points / occupied area)
  int version = 0;            // canopy.detections version read
  int candidates = 0, found = 0;
  std::map<std::string, int> by_level;   // "model" / "class" -> detections
  std::map<std::string, int> by_class;   // "<level>: <class or model>" -> detections
  std::map<std::string, int> by_reason;  // rejected candidates by reason (v1: none, failed)
  std::string warning;                   // the detections' warning ("" when none)
  // Labelled tiles (score.json and the labels):
  bool scored = false;
  double match_radius_m = 0;
  int vehicles = 0, clear = 0;     // labelled vehicles, of them "clear"
  int uncertain = 0;               // labelled uncertain objects
  Count recall_all, recall_clear;  // true vehicles matched / labelled (all; visibility clear)
  int tp = 0, fp = 0;              // score's matches and false alarms
  int fp_on_uncertain = 0;         // of the false alarms: within the match radius of an uncertain object
  Count precision;                 // tp of (detections − those on uncertain objects)
  Count class_right;               // matched detections whose group (car / van …) is the label's, of
                                   // the matched detections that carry a group
  int matched_without_group = 0;   // matched detections with no group (model level, no class)
  // The labelled vehicles no detection matched, by score's fate ("no candidate", "refused:
  // <reason>", "taken", "off centre"; "unknown" for a score written before stop 71), over the
  // clear ones and over all; and the object densities of the refused candidates (all lost).
  std::map<std::string, int> lost_clear, lost_all;
  std::vector<double> refused_density;
};

// A real tile's source and licence for the report's table (share/real/README.md), by the tile's
// name; "–" for a name it does not know.
std::string real_tile_source(const std::string& name);

// Reads one tile's artifacts (a missing file is a tile not run / not finished / not scored; a
// malformed one throws common::DataError naming it).
RealTile read_real_tile(const RealTileFiles& files);

// The section (Markdown): per tile what ran, the candidates and their fate, the detections;
// false alarms per hectare on the plots without vehicles (exact Poisson interval), recall,
// precision and class accuracy on the labelled tiles (Wilson intervals), time per tile against
// `target_s`. `timeout_s`: the time box of a tile (mk/real.mk REAL_TIMEOUT), 0 unknown.
std::string real_markdown(const std::vector<RealTile>& tiles, int timeout_s, double target_s = 60);

// classify's ablation on the real tiles (mk/real.mk REAL_CLASSIFY_ABLATION: the workflow run again
// with the parameter file `config`; `index` k > 0: its (k + 1)-th, REAL_CLASSIFY_ABLATION_<k + 1>):
// per tile with an ablation run (matched to `tiles` by name), canopy's figures beside the
// ablation's — recall (clear, all), precision and class right on the labelled tiles (and over all
// of them), false alarms on the plots; "" when `ablation` is empty. A `config` of the form
// TILE_MODEL_DENSITY=<value> is the model level's ablation (the workflow with classify.ini and the
// model level at that density): its own heading, and each tile's model-level detections besides.
std::string real_ablation_markdown(const std::vector<RealTile>& tiles, const std::vector<RealTile>& ablation,
                                   const std::string& config, int index = 0);

}  // namespace canopy::report
