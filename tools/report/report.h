// report: the experiment's tables, failure analysis and timings as Markdown and CSV
// (thesis §6.4 tables 6.1–6.5 and Table A.1, with the thesis's figures beside ours).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "canopy/formats/csv_table.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/scene_score.h"
#include "canopy/documents/segment_graph.h"
#include "canopy/documents/stage_time.h"
#include "canopy/documents/verdict.h"

namespace canopy::report {

// Wall time, peak memory and CPU of one stage run (tools/stagerun's .time files,
// documents::read_stage_time; a malformed one is an error naming it); the thesis's results table
// (formats::parse_thesis_csv); the one number formatter of the report's tables and Markdown
// (formats::format_number).
using formats::format_number;
using formats::parse_thesis_csv;
using documents::StageTime;
using formats::ThesisRow;

// A method's name in the report's tables: gmatch and verify as canopy's, vfh and fpfh as the
// PCL baseline's (VFH, FPFH); any other name as it is.
std::string method_label(const std::string& method);

// Target surface area at each stage of one trial (areas.json of tools/areas, read by
// documents/areas.h: OUT/.../noise-<mm>/areas.json), m².
struct AreaRow {
  bool present = false;
  double visible = 0;   // visible in the labelled noise-free scan
  double samples = 0;   // what the fitvox samples stand for
  double mesh = 0;      // cocone mesh
  double segments = 0;  // every ncut segment
  double matched = 0;   // gmatch's X largest segments
};

// verify's verdict.json of one trial: absent (verify not run), empty (verify failed; recorded by
// stagerun --record-failure) or read.
enum class VerdictStatus { missing, failed, read };

// One trial: an object seen in a scene at a noise level, matched against the modelbase.
struct Case {
  std::string object, scene;
  int noise_mm = 0;
  documents::MatchResult match;
  documents::SegmentGraph segments;
  std::map<std::string, StageTime> times;  // stage name -> time (addnoise, fitvox, ...)
  AreaRow areas;
  VerdictStatus verdict_status = VerdictStatus::missing;
  documents::Verdict verdict;  // when verdict_status == read
};

// A variant of the experiment with one project default undone (out/ablation/<name>/).
struct Ablation {
  std::string name;
  std::string change;                       // e.g. "ncut --exponent squared"
  std::map<std::string, int> correct_rank;  // "<object>/<scene>/<noise>" -> rank of the right model
  int failed = 0;                           // trials where a stage failed (rank 0)
};

struct Inputs {
  std::vector<std::string> objects, scenes;
  std::vector<int> noises;
  std::vector<Case> cases;                                // objects x scenes x noises, in order
  std::map<std::string, documents::SegmentGraph> models;  // the modelbase, by model name
  std::map<std::string, StageTime> render_times;          // "<object>/<scene>" -> rangetrace run
  std::map<std::string, int> render_views;                // scene -> views per rendering
  std::map<std::string, ThesisRow> thesis;                // "<object>/<scene>/<noise>" -> row
  std::vector<std::string> figures;                       // figure paths relative to the report
  std::vector<Ablation> ablations;
};

struct Params {
  int max_segments = 15;            // gmatch's X: segments considered for the diagnostics
  double overseg_ratio = 1.5;       // target segments / model segments above this = over-segmented
  double missing_area_ratio = 0.6;  // target area / model area below this = missing area
  double spurious_share = 0.2;      // area share of non-target segments among the X largest
};

// Throws common::UsageError naming the option of the first parameter out of its range:
// --max-segments >= 1, --overseg-ratio > 0, --missing-area-ratio >= 0, --spurious-share in
// [0, 1] (all finite).
void validate(const Params& params);

// Ground-truth diagnostics of one case.
struct Diagnosis {
  int target_segments = 0, model_segments = 0, spurious_segments = 0;
  double target_area = 0, model_area = 0, spurious_area_share = 0;
  bool over_segmented = false, missing_area = false, spurious = false;
  std::string best_model;
  double correct_score = 0, entropy = 0;
  int correct_rank = 0;
};

Diagnosis diagnose(const Case& c, const documents::SegmentGraph* model, const Params& p);

// Area retained per noise level over the trials with areas: ratios of sums (stage area summed
// over the trials / visible area summed over the same trials), and the matched area relative to
// the 0 mm matched area of the same object/scene pairs (pairs with both levels only).
struct AreaSummary {
  int noise_mm = 0;
  int trials = 0;
  double visible = 0;                                       // m², summed
  double samples = 0, mesh = 0, segments = 0, matched = 0;  // fractions of visible
  double matched_vs_0 = 0;  // Σ matched(noise) / Σ matched(0 mm); 0 when no pair has both
  int pairs_vs_0 = 0;
};
std::vector<AreaSummary> summarize_areas(const Inputs& in);

// verify's answer on one trial judged against the truth (the trial's object). On the thesis
// trials every object is rendered at heading 0 at the origin (docs/decisions/verify.md §8), so
// the true model -> candidate pose is the identity: position error = |translation| of the chosen
// hypothesis's pose, heading error = |heading| wrapped to [0, 180] degrees. A right model whose
// heading error exceeds 90 degrees is the 180-degree flip and counts as wrong (outcome flipped).
enum class Outcome { not_run, failed, right, flipped, wrong_model, none };
const char* outcome_name(Outcome o);

struct Judgement {
  Outcome outcome = Outcome::not_run;
  std::string answer;         // model name, "none", or "" (not run / failed)
  double confidence = 0;      // when answered (right, flipped, wrong_model, none)
  bool posed = false;         // the answer is the true model and carries a pose
  double position_error = 0;  // m
  double heading_error = 0;   // degrees, in [0, 180]
  bool gmatch_right = false;  // gmatch ranked the true model first (the ablation without verify)
  std::string gmatch_model;   // gmatch's rank-1 model ("" when it ranked none)
};
Judgement judge_verdict(const Case& c);

// Counts over a set of trials with a verdict.json (read or failed).
struct VerifyTally {
  int trials = 0, right = 0, flipped = 0, wrong_model = 0, none = 0, failed = 0;
  int gmatch_right = 0;  // of the same trials
};

// One reliability bin: confidence in [lo, hi) (the last bin includes 1), over the answers
// (model or none; failed trials have no confidence).
struct ReliabilityBin {
  double lo = 0, hi = 0;
  int answers = 0, right = 0;
};

struct VerifySummary {
  int not_run = 0;  // trials without verdict.json
  VerifyTally all;
  std::map<std::string, VerifyTally> per_object;
  std::map<int, VerifyTally> per_noise;
  std::vector<ReliabilityBin> reliability;  // bins 0-0.5, 0.5-0.7, 0.7-0.8, 0.8-0.9, 0.9-1
  // Pose error of the right answers (median and 90th percentile, linear interpolation between
  // order statistics).
  int posed = 0;
  double position_median = 0, position_p90 = 0, heading_median = 0, heading_p90 = 0;
  std::vector<Judgement> judgements;  // one per case, in Inputs::cases order
};
VerifySummary summarize_verify(const Inputs& in);

// Percentile q in [0, 1] of values (linear interpolation between order statistics); 0 when empty.
double percentile(std::vector<double> values, double q);

// areas.json of one trial; a missing file gives present = false.
AreaRow read_areas(const std::string& path);

// Thesis recognition rates as printed (Tables 6.1–6.5), percent, by object; the tables' own
// rank-1 counts are computed from share/thesis/results.csv and shown beside them.
extern const std::map<std::string, int> kThesisPrinted;

// A rank-1 count over trials.
struct Rate {
  int right = 0, trials = 0;
};

// One ablation variant's rank-1 rates: per object (Inputs::objects order) and over its trials.
struct AblationRates {
  std::vector<Rate> per_object;
  Rate all;
  int failed = 0;  // trials where a stage failed (Ablation::failed)
};

// One stage summed over its runs (.time files present).
struct StageTotal {
  int runs = 0;
  double seconds = 0;      // summed wall time
  double peak_mb = 0;      // largest peak memory of one run
  int cpu_runs = 0;        // runs whose .time file has CPU columns (older files have not)
  double cpu_seconds = 0;  // summed user + system CPU of those runs
  void add(const StageTime& t);
};

// A table cell for the CPU seconds of `cpu_runs` out of `runs` runs: `number` (the formatted
// sum) when every run has it, "–" when none has, "<number> (k of n runs)" between.
std::string cpu_cell(const std::string& number, int cpu_runs, int runs);

// Every number of the report, computed from the inputs; render() only formats them.
struct Numbers {
  std::vector<Diagnosis> diagnoses;               // one per case, Inputs::cases order
  std::map<std::string, Diagnosis> by_key;        // "<object>/<scene>/<noise>" -> its diagnosis
  std::map<std::string, Rate> per_object;         // canopy's rank-1 rate (every Inputs::objects entry)
  std::map<std::string, Rate> thesis_per_object;  // the thesis table's, over the trials it lists
  Rate all, thesis_all;
  double mean_rate = 0;         // mean of the per-object rates (%), over Inputs::objects
  double thesis_mean = 0;       // mean of kThesisPrinted over the objects it has (%)
  int thesis_printed = 0;       // objects with a printed thesis rate
  bool thesis_objects = false;  // the objects are the thesis's five (its overall ≈79% applies)
  // Trials whose correct model is not rank 1, and how many show each diagnosed cause.
  int failed = 0, over_segmented = 0, missing_area = 0, spurious = 0, unexplained = 0;
  std::vector<AblationRates> ablations;  // Inputs::ablations order
  std::vector<AreaSummary> areas;        // summarize_areas
  VerifySummary verify;                  // summarize_verify
  // Trial stages (addnoise ... verify, always present, zero without runs) and rangetrace (the
  // renderings, Inputs::render_times).
  std::map<std::string, StageTotal> stages;
  int render_images = 0;         // images of the renderings (Inputs::render_views per scene)
  double total_seconds = 0;      // summed over the stages but verify (beyond the thesis)
  double total_cpu_seconds = 0;  // ... their CPU, over the runs with CPU columns
  int total_runs = 0, total_cpu_runs = 0;
};

Numbers compute(const Inputs& in, const Params& p);

// The images of one rendering (the time table's "(N images)"): the scan's highest view_idx + 1;
// when the scan is gone (a scan is deleted after its last reader unless KEEP=1, so a report made
// again later finds none), the view count rangetrace wrote in the scan's stage log
// ("rangetrace: wrote N points (model, scene, V views) to ..."); 0 when neither says.
int render_views(const std::string& scan);

struct Outputs {
  std::string markdown;
  std::string cases_csv, scores_csv, times_csv;
  // Area retained per stage and noise level in scores.csv's layout (object = stage, scene =
  // "all", score = fraction of the visible area), so `figures plot` draws it.
  std::string areas_csv;
  // verify's answer per trial: object,scene,noise_mm,answer,confidence,correct,gmatch_rank1,...
  std::string verdicts_csv;
};

// The Markdown and CSV tables of the numbers (the inputs give the trials' order and names).
Outputs render(const Inputs& in, const Params& p, const Numbers& numbers);

// render(in, p, compute(in, p)).
Outputs run(const Params& params, const Inputs& inputs);

// ---- the scene experiment (issue 16; docs/decisions/scene-experiment.md) -----------------
// The numbers are computed by `score` (results/scenes/score.json, canopy.scene_score v1) and by
// scene_times below; scene_markdown only renders them.

// One run of the scene experiment: a tile at one noise level. dir = the directory of its
// detections.json (…/tile-<seed>/noise-<mm>); its rendering is dir/.. (rendered once, shared
// by the noise levels).
struct SceneRun {
  std::string dir;
  double area_ha = 0;
};

// Wall time, CPU and peak memory of one stage summed over the scene experiment, from the .time
// files of tools/stagerun: rangetrace = <tile>/scan.pcd (each rendering once, per hectare of
// rendered tiles), addnoise = <run>/scan.pcd, detect = <run>/detect, plan = <run>/cands.mk,
// fitvox … verify = <run>/cands/<id>/{samples.pcd, mesh.ply, segments.json, match.json,
// verdict.json}, collect = <run>/detections.json, topview = <run>/scored.png; per hectare of
// runs for every stage but rangetrace. A missing .time file is not counted.
struct SceneStageTime {
  std::string stage;
  int runs = 0;            // .time files read
  double seconds = 0;      // summed wall time
  double area_ha = 0;      // hectares the stage covered (renders, or runs)
  double per_ha = 0;       // seconds / area_ha (0 when no area)
  double peak_mb = 0;      // largest peak memory of one run
  int cpu_runs = 0;        // runs with CPU columns
  double cpu_seconds = 0;  // summed user + system CPU of those runs
};
std::vector<SceneStageTime> scene_times(const std::vector<SceneRun>& runs);
// Whether a scene stage is canopy's own (not the baseline's, "baseline-*", nor a verify ablation's
// run, "verify-*"): the others are listed only when they ran and are not canopy's cost.
bool canopy_stage(const std::string& stage);

// The runs named by a score document's "tiles" (dir = directory of each "detections").
std::vector<SceneRun> scene_runs(const documents::SceneScore& score);
// How many models gmatch ranked (m), how many of them canopy's verify checked (k) and how many the
// verify ablation checked (k_ablation; 0 without its verdict): the first candidate of the runs with a
// match.json (not a failed gmatch's empty one) and its verdict.json (every candidate is matched
// against the whole modelbase, and verify checks min(top-k, m)); zeros when none is found.
struct SceneRankedModels {
  std::size_t m = 0, k = 0, k_ablation = 0;
};
SceneRankedModels scene_ranked_models(const documents::SceneScore& score);

// The report's "Scene experiment" section (Markdown) and the times as CSV
// (stage,runs,seconds,area_ha,seconds_per_ha,peak_mb,cpu_seconds,cpu_runs). figures_dir: the scene figures'
// directory relative to report.md ("scenes"). collect_ablation: the score of collect's ablation
// (mk/scenes.mk SCENE_COLLECT_ABLATION, `collect --coarse-none-below 0`; read from
// collect_ablation_path), whose reliability table is shown beside canopy's when it scores
// exactly canopy's runs (else a note names the stale file).
// classify_ablations: the scene experiment's classify ablations in their order (mk/scenes.mk
// SCENES_CLASSIFY_ABLATION, SCENES_CLASSIFY_ABLATION_2; report --tile-classify-ablation[-2]), each
// shown beside canopy in the subsection "classify's ablations on the scene experiment" when it
// scores exactly canopy's runs (else a note names the stale file); one without a score is said
// not to have run.
struct SceneClassifyAblation {
  std::string config;                            // the parameter file it classified with ("" when not run)
  std::string path;                              // its score.json
  const documents::SceneScore* score = nullptr;  // null: not run
};
// The scene experiment's verify ablation (issue 29, "what each stage adds": what gmatch's ranking adds,
// mk/scenes.mk SCENES_VERIFY_ABLATION = --top-k=3 against verify's top-k 5): shown with the baseline's
// methods, and in "What gmatch adds" when it checked another number of hypotheses than canopy.
struct SceneVerifyAblation {
  std::string options;                           // verify's options it ran with
  std::string path;                              // its score.json
  const documents::SceneScore* score = nullptr;  // null: not run
};
// baselines: the baseline methods that ran (vfh, fpfh, size, fpfh-verify; mk/scenes.mk, report
// --tile-baselines): only their <csv dir>/baseline-<method>/score.json are read, so a method turned
// off is not shown from its old score; null: every method whose score.json is there (by hand).
std::string scene_markdown(const documents::SceneScore& score, const std::vector<SceneStageTime>& times,
                           const std::string& figures_dir,
                           const documents::SceneScore* collect_ablation = nullptr,
                           const std::string& collect_ablation_path = "",
                           const std::vector<SceneClassifyAblation>& classify_ablations = {},
                           const SceneVerifyAblation& verify_ablation = {},
                           const std::vector<std::string>* baselines = nullptr);
std::string scene_times_csv(const std::vector<SceneStageTime>& times);
// The subsection "Time per hectare and peak memory per stage" of the scene section.
std::string scene_times_markdown(const std::vector<SceneStageTime>& times);
// Whether `method` names one of the scene experiment's baseline methods (scene_markdown's baselines).
bool is_scene_baseline_method(const std::string& method);

// "k/n = r% [lo, hi]": the rate with Wilson's 95% interval at `units` independent units
// (common::wilson_effective; units = n when every trial is its own sample, fewer where trials
// share a render); "–" when n = 0.
std::string rate_ci_units(int k, int n, double units);

}  // namespace canopy::report
