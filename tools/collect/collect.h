// collect: one tile's candidates index (detect) + per-candidate verdicts (verify) ->
// detections.json (canopy.detections v1) and a GeoJSON FeatureCollection of the detections in
// the tile's coordinates (formats/README.md "Detections"; docs/decisions/scene-experiment.md).
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "canopy/common/density_scale.h"
#include "canopy/documents/candidates.h"
#include "canopy/formats/provenance.h"

namespace canopy::collect {

using Matrix = std::array<double, 16>;  // 4 x 4 row-major, float64
using Corner = std::array<double, 2>;

struct Candidate {
  std::string id;
  Matrix transform{};  // candidate frame -> tile frame
  double length = 0, width = 0;
  std::optional<double> density;  // object points per m² of the footprint (index "density", or
                                  // object_points / (length x width)); none in older indexes
};

struct Index {
  std::string name;  // file, as given
  std::string tile;  // the tile detect read, as it recorded it
  // The tile's CRS as detect read it from the file ("EPSG:<code>") and where; "" when none.
  std::string crs, crs_from;
  std::vector<Candidate> candidates;
  decltype(documents::Candidates::density) density;  // the index's "density" object (detect.md §7), or null
  std::vector<std::string> warnings;                 // what detect warned about the tile (index "warnings")
};

// The density of model-level recognition (common/density_scale.h: the lowest object density at
// which the density rule's chain runs; docs/decisions/density-scale.md).
constexpr double kModelDensity = common::kModelLevelDensity;
// The object density (points/m²) below which classify answers too_sparse by default (classify's
// --min-density: common/density_scale.h, as kModelDensity; tests/collect checks they agree): what
// collect states a tile without candidates against when no class answer says it.
constexpr double kClassDensity = common::kClassLevelDensity;

// The model chain's artifacts beside a candidate's verdict, in the order make runs their stages
// (mk/scenes.mk cand_rule: fitvox, cocone, ncut, gmatch; verify writes the verdict last). A
// stage that failed as a result (stagerun --record-failure) leaves its artifact empty, and the
// later ones fail on it in turn.
inline constexpr const char* kModelChainArtifacts[] = {"samples.pcd", "mesh.ply", "segments.json",
                                                       "match.json"};

struct Verdict {
  std::string name;        // file, as given
  bool present = true;     // false: there is no such file (a class-level candidate has no verdict.json)
  bool failed = false;     // an empty file: the candidate's chain failed (stagerun --record-failure)
  std::string failed_log;  // failed: the log of the chain's first failed stage (failed_stage_log); ""
                           // when not looked for (parse_verdict): then the verdict's own <name>.log
  std::string candidate;   // the points verify checked ("candidate"), as it was given them
  std::string level;       // "level" when given ("class" for classify's answers)
  std::string model;       // "" = none
  std::string cls;         // "class", when the verdict has one
  std::string group;       // "group", when the verdict has one
  double confidence = 0;
  std::optional<Matrix> pose;       // model -> candidate
  std::optional<Matrix> pose_tile;  // model -> tile
  // classify's answer (docs/decisions/classify.md §9), when the verdict has them:
  std::string reason, detail;     // why none (too_sparse, vegetation_like, ...), one sentence
  std::string refused_on;         // what classify's none rests on: density, surface, size, shape ("": unsaid)
  std::optional<double> density;  // object points per m² of its rectangle
  std::optional<double> density_class, density_model;  // "density_needed"
  std::optional<std::array<double, 3>> size;           // L W H (m)
  std::optional<double> heading_ambiguity;             // degrees (180: front and back unknown)
  // classify's measured rectangle, whatever its answer (documents::Verdict).
  std::optional<std::array<double, 3>> measured_size;
  std::optional<std::array<double, 2>> measured_centre;
  std::optional<double> measured_heading;
  double measured_edge_correction = 0;
};

// What a candidate is answered from: its model chain's verdict (verify) and classify's
// class.json, either of which may be absent (present = false).
struct Answers {
  Verdict model;
  Verdict cls;
};

// The top-view rectangle of a model in its own frame: x in [x0, x1], y in [y0, y1]; z1 its
// highest point above the model frame's ground (z = 0).
struct ModelBox {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0, z1 = 0;
};

// The calibration of the confidence a final answer states (issue 29; docs/decisions/verify.md
// §16): p' = logistic(bias + slope * logit(p)) (Platt scaling) of the confidence the answering
// level gave, per source: verify's model answer, classify's class answer, verify's none where
// both levels rejected (or classify did not answer), classify's none where the model chain did
// not run. The identity (bias 0, slope 1) states the level's own confidence. verify's none
// has a map by the candidate's object density (verify.md §19): `none_coarse` below
// Params::coarse_none_below (the density rule's coarse candidates), `none_dense` at or above it
// (and for an unknown density); `none`, the one map of every verify none (§16), is used only
// with the split off (coarse_none_below 0: the ablation).
struct PlattMap {
  double bias = 0, slope = 1;
};
struct Calibration {
  std::string name;  // the file it was read from; "" = none (every answer states its level's own
                     // confidence, as before issue 29's §16: the ablation)
  PlattMap model, cls, none, none_class, none_dense, none_coarse;
};
// The calibration file (formats/README.md "Confidence calibration"; read by formats/ini.h,
// docs/decisions/ini.md): `key = value` lines (';' or '#' starts a comment), every key of
// kCalibrationKeys exactly once, values decimal numbers, slopes > 0 (a calibration never
// reorders one level's answers). DataError naming the file (and the line) otherwise.
Calibration parse_calibration(const std::string& text, const std::string& name);
// The keys of the calibration file, in the order they are read.
inline constexpr const char* kCalibrationKeys[] = {
    "model-bias",      "model-slope",      "class-bias",       "class-slope",
    "none-bias",       "none-slope",       "none-class-bias",  "none-class-slope",
    "none-dense-bias", "none-dense-slope", "none-coarse-bias", "none-coarse-slope"};
// logistic(bias + slope * logit(p)), p clamped to [1e-9, 1 - 1e-9]; p itself for the identity.
double calibrated(const PlattMap& map, double p);

struct Params {
  std::string crs;                        // --crs, "EPSG:<code>"; "" = the index's (the tile's), if any
  std::map<std::string, ModelBox> boxes;  // by model name; a model without one uses the candidate footprint
  // The size-only ablation (issue 29; docs/decisions/scene-experiment.md): no model chain and
  // none of classify's decisions; every candidate classify measured (its "measured" rectangle:
  // the object's points above the ground, whatever classify answered) becomes a model-level
  // detection of the model in `boxes` nearest to that length, width and height (the length and
  // width with classify's edge correction added back, as the model's box is the full extent)
  // (nearest_by_size) when each of the three lies within size_gate (relative) of the model's,
  // placed with its box centre on the measured rectangle (size_only_pose); confidence = 1 - the
  // largest relative difference / size_gate. Other candidates are rejected as without it.
  bool size_only = false;
  double size_gate = 0.25;
  // A model-level answer (verify's model) with a confidence below `contradicted_below` gives
  // way to classify's class answer when classify named a class and neither its class nor its
  // group is the model's class (model_contradicted): verify's calibrated confidence says the
  // model is more likely wrong than right, and the class level says what else it is. 0 = off
  // (the model answer always first, as before). docs/decisions/open-set.md "Sixth round".
  double contradicted_below = 0.5;
  // At what level classify's class answer must differ to contradict (docs/decisions/open-set.md
  // "Thirteenth round"): by default its group (the taxonomy's, common/vehicle_classes.h) must differ from
  // the model class's group, since classify's answer states only the group (its confidence's
  // margin is over the other groups; within a group its classes' size ranges overlap and it
  // picks the nearest); false = the sixth round's rule, a class and group that both differ from
  // the model's class (a pickup model contradicted by a car answer: the ablation).
  bool contradicted_by_group = true;
  // A model-level answer with a confidence below `refused_below` gives way to classify's none
  // when classify refused the candidate on its shape or its surface (refused_by_shape: a flat box,
  // an oval, no roof, a drawbar, porous or rough; not its density, nor a size no class's ranges
  // hold): the candidate is rejected with classify's reason. 0.8 by default: below it verify's
  // model answers on development tiles were right 5 times in 14, at 0.8 and above every time
  // (docs/decisions/verify.md §15). 0 = off (the model answer first, as before).
  // docs/decisions/open-set.md "Seventh round".
  double refused_below = 0.8;
  // The stated confidences of the final answers (never which answer is given: applied after
  // every decision above). Empty name: none. Not applied to --size-only's answers.
  Calibration calibration;
  // verify's none of a candidate whose object density (the index's, as the density rule reads
  // it) is below this states calibration.none_coarse, any other verify none calibration.none_dense
  // (docs/decisions/verify.md §19: on development tiles 27 of the 28 wrong verify nones were
  // such candidates). The density rule's dense end (common/density_scale.h kDenseDensity, 370
  // points/m²): the candidates whose model chain ran at a coarser scale. A candidate of unknown
  // density (an older index) is not coarse. 0 = off: every verify none through calibration.none
  // (the ablation; as before §19).
  double coarse_none_below = common::kDenseDensity;
  // A class-level answer (classify's class, a detection only when no model answer is given)
  // whose stated confidence (the one collect writes: through calibration.cls when a calibration
  // is given) is below `class_accept` is not a detection: the candidate is rejected with reason
  // kLowConfidence, its detail naming the class, its confidence and the threshold (issues 27,
  // 29; docs/decisions/open-set.md "Seventeenth round"). Model answers are untouched. 0 = off
  // (every class answer a detection, as before). In [0, 1]; not applied to --size-only.
  double class_accept = 0;
  // The classes of models (collect --model-classes, documents::parse_model_classes: e.g.
  // share/models/classes.csv): a model-level detection whose answer carries no class (verify's
  // verdict on a modelbase without <model>.class files, --size-only's answers) is written with
  // its model's class here and that class's group (common::class_group); an answer's own class
  // is written as it is, with its group (its own, else the class's: verify writes no group); a
  // model not here stays without. Only what the written detection names: applied after every
  // decision above, which read the answers as they are (model_contradicted sees no class where
  // the verdict has none). Empty: none (as before).
  std::map<std::string, std::string> model_classes;
};

// The rejection reason of a class answer below Params::class_accept.
inline constexpr const char* kLowConfidence = "low_confidence";

// Whether classify's class answer k contradicts verify's model answer v: v names a model of a
// known class, k names a class, and neither k's class nor its group is v's class; by_group: nor
// is k's group (or, without one, its class's) v's class's group (the taxonomy's,
// common/vehicle_classes.h class_group: a family's group, any other name its own).
bool model_contradicted(const Verdict& v, const Verdict& k, bool by_group = true);
// Whether classify's answer k refuses, on the candidate's shape or surface (refused_on "shape"
// or "surface"), verify's model answer v: v names a model and k names no class.
bool refused_by_shape(const Verdict& v, const Verdict& k);
// Largest relative difference |s - m| / m of a size (L W H) from a model box's (longer side,
// shorter side, z1); infinity for a box of zero extent.
double size_difference(const std::array<double, 3>& size, const ModelBox& box);

// The model of `boxes` whose (length, width, height) — the longer and shorter side of its
// rectangle and z1 — is nearest to `size` (L W H, m) in Euclidean distance; ties: the first
// name. "" when `boxes` is empty.
std::string nearest_by_size(const std::array<double, 3>& size, const std::map<std::string, ModelBox>& boxes);
// model -> tile for a model placed by size on classify's rectangle frame `rect` (rectangle
// centre, x along its length -> tile): the model's rectangle centre on the rectangle's, its
// longer side along the rectangle's length (turned 90° about z when the model's y side is the
// longer).
Matrix size_only_pose(const Matrix& rect, const ModelBox& box);

// Throws common::UsageError naming --crs when crs is neither empty nor EPSG:<1-6 digits>.
void validate(const Params& params);

Index parse_index(const std::string& text, const std::string& name);
// A verdict file that does not exist (present = false).
Verdict absent_verdict(const std::string& name);
// A verdict (verify's or classify's canopy.verdict) through documents::parse_stage_verdict: an
// empty text is a failed candidate; any refusal of documents::parse_verdict names the file.
Verdict parse_verdict(const std::string& text, const std::string& name);
// The file at `path` (documents::read_stage_verdict): absent (present = false) when there is
// no such file, else as parse_verdict.
Verdict read_verdict(const std::string& path);
// The log of the first failed stage of the model chain whose verdict is `verdict` (a failed one):
// beside it, the first of kModelChainArtifacts, then the verdict itself, that exists and is
// empty, with ".log" appended; the verdict's own "<verdict>.log" when none is (another layout).
// read_verdict sets Verdict::failed_log so.
std::string failed_stage_log(const std::string& verdict);

// Whether a verdict's "candidate" (the points verify was given) names candidate `id`: its file
// stem is the id (detect's <id>.pcd) or its directory is named so (<id>/samples.pcd).
bool names_candidate(const std::string& points, const std::string& id);
// The verdict belongs to candidate `id` of the index in `index_dir`: DataError naming the
// verdict file unless names_candidate(); and when those points exist (seen from the working
// directory), they must be <index_dir>/<id>.pcd or lie in <index_dir>/<id>/ or in the verdict's
// own directory, or have the same bytes as the file of their name there (a copy of the tile's
// directory, whose verdicts name the original's points): another tile's candidate of the same id
// is refused too. Failed verdicts pass.
void check_verdict_of(const Verdict& verdict, const std::string& id, const std::string& index_dir);

// p = a * b (4 x 4 row-major).
Matrix multiply(const Matrix& a, const Matrix& b);
// Heading, pitch, roll in degrees of the rotation of m (R = Rz(heading) Ry(pitch) Rx(roll)).
std::array<double, 3> euler_degrees(const Matrix& m);

struct Outputs {
  std::string detections;  // canopy.detections v2
  std::string geojson;     // FeatureCollection
  int found = 0, none = 0, failed = 0;
  int model_level = 0, class_level = 0;
  // The candidates whose model chain ran (a verdict file, empty or not) and of them those whose
  // chain failed (an empty verdict), whatever answered them in the end (classify's answer hides
  // a failed chain from found / none / failed): detections.json's "model_chain_ran" and
  // "model_chain_failed".
  int chain_ran = 0, chain_failed = 0;
  std::map<std::string, int> by_reason;
  std::string summary;  // one line: the counts by level and by reason
  std::string warning;  // "" or one sentence (most candidates rejected for one reason, ...)
};

// answers[i] belongs to index.candidates[i] (DataError naming the verdict when its candidate
// does not name it, names_candidate). Per candidate: a model-level detection when the model
// verdict names a model; else a class-level one when classify's names a class; else a
// rejection with classify's reason (or "none" / "failed" from the model verdict when there is
// no class answer). `provenance` is written as is.
Outputs collect(const Index& index, const std::vector<Answers>& answers, const Params& params,
                const formats::Provenance& provenance);

// One tile: its index, the answers per candidate (answers[i] of index.candidates[i]) and who
// writes the documents from what (formats::provenance_json).
struct Inputs {
  Index index;
  std::vector<Answers> answers;
  formats::Provenance provenance;
};

// collect(inputs.index, inputs.answers, params, inputs.provenance).
Outputs run(const Params& params, const Inputs& inputs);

// The make plan of a tile: the candidate ids, each one's candidate-to-tile transform (16
// comma-separated numbers, row-major, as verify --transform takes them) and level, as make
// variables <key>_CANDS, <key>_TRANSFORM_<id> and <key>_LEVEL_<id> (mk/scenes.mk): "model"
// when the candidate's object density is at least model_density (or unknown: an older
// index), else "class" (classify only). Ids are plain names (parse_index). With `scale`, each
// model-level candidate of known object density below the dense end (common/density_scale.h)
// also gets the density rule's options per stage, <key>_FITVOX_<id>, <key>_COCONE_<id> and
// <key>_NCUT_<id> (e.g. "--voxel 175mm"); the others get none, and their stages run with
// today's parameters.
std::string plan(const Index& index, const std::string& key = "TILE", double model_density = kModelDensity,
                 bool scale = true);

}  // namespace canopy::collect
