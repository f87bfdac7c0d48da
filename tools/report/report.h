// report: the experiment's tables, failure analysis and timings as Markdown and CSV
// (thesis §6.4 tables 6.1–6.5 and Table A.1, with the thesis's figures beside ours).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "canopy/formats/json_io.h"

namespace canopy::report {

// Wall time and peak memory of one stage run (from scripts/stage.sh's .time files).
struct StageTime {
  double seconds = 0;
  double peak_mb = 0;
  bool present = false;
};

// One trial: an object seen in a scene at a noise level, matched against the modelbase.
struct Case {
  std::string object, scene;
  int noise_mm = 0;
  formats::MatchResult match;
  formats::SegmentGraph segments;
  std::map<std::string, StageTime> times;  // stage name -> time (addnoise, fitvox, ...)
};

struct ThesisRow {
  double score = 0;
  int rank = 0;
  double entropy = 0;
};

// A variant of the experiment with one project default undone (out/ablation/<name>/).
struct Ablation {
  std::string name;
  std::string change;  // e.g. "ncut --exponent squared"
  std::map<std::string, int> correct_rank;  // "<object>/<scene>/<noise>" -> rank of the right model
  int failed = 0;                            // trials where a stage failed (rank 0)
};

struct Inputs {
  std::vector<std::string> objects, scenes;
  std::vector<int> noises;
  std::vector<Case> cases;                               // objects x scenes x noises, in order
  std::map<std::string, formats::SegmentGraph> models;   // the modelbase, by model name
  std::map<std::string, StageTime> render_times;         // "<object>/<scene>" -> rangetrace run
  std::map<std::string, int> render_views;               // scene -> views per rendering
  std::map<std::string, ThesisRow> thesis;               // "<object>/<scene>/<noise>" -> row
  std::vector<std::string> figures;                      // figure paths relative to the report
  std::vector<Ablation> ablations;
};

struct Params {
  int max_segments = 15;            // gmatch's X: segments considered for the diagnostics
  double overseg_ratio = 1.5;       // target segments / model segments above this = over-segmented
  double missing_area_ratio = 0.6;  // target area / model area below this = missing area
  double spurious_share = 0.2;      // area share of non-target segments among the X largest
};

// Ground-truth diagnostics of one case.
struct Diagnosis {
  int target_segments = 0, model_segments = 0, spurious_segments = 0;
  double target_area = 0, model_area = 0, spurious_area_share = 0;
  bool over_segmented = false, missing_area = false, spurious = false;
  std::string best_model;
  double correct_score = 0, entropy = 0;
  int correct_rank = 0;
};

Diagnosis diagnose(const Case& c, const formats::SegmentGraph* model, const Params& p);

struct Output {
  std::string markdown;
  std::string cases_csv, scores_csv, times_csv;
};

Output run(const Inputs& in, const Params& p);

// Thesis results table (share/thesis/results.csv): object,scene,noise_mm,score,rank,entropy.
std::map<std::string, ThesisRow> parse_thesis_csv(const std::string& text, const std::string& name);

}  // namespace canopy::report
