// gmatch: inexact, incomplete, depth-first tree matching of an object's segment graph against
// every model of a modelbase (thesis ch. 6, PIPELINE.md §7), ranking the models by score and
// reporting the entropy of the scores (Eq. 6.14-6.15).
//
// Inputs: segment graphs as read by canopy::formats (areas m^2, centroids m, unit normals,
// thickness and elongation in [0, 1]). The logic does no I/O except read_modelbase().
// Decisions where the thesis is silent or inconsistent: docs/decisions/gmatch.md.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/documents/match_result.h"
#include "canopy/documents/segment_graph.h"

namespace canopy::gmatch {

// How the pairwise orientation error E_O compares normals.
enum class OrientationForm {
  kRelative,  // (2/pi) |angle(n_si, n_sj) - angle(n_mi, n_mj)|: invariant to heading/position
  kThesis,    // Eq. 6.7 as printed: (2/pi) |acos(n_si.n_mi) - acos(n_sj.n_mj)|
};

// Whether a normal's sign carries information.
enum class NormalSign {
  kAxial,   // n and -n are the same axis: angles use |cos|, in [0, pi/2]
  kSigned,  // angles use cos, in [0, pi]
};

// How the four error terms are combined into the total error E (score S = 1 - E).
enum class ErrorForm {
  kBounded,  // S = (1-mean E_U)^eu (1-mean E_O)^eo (1-mean E_D)^ed (coverage)^ea, in [0, 1]
  kThesis,   // Eq. 6.12 as printed: E = (1/x) C_U^eu C_O^eo C_D^ed C_A^ea; S = max(0, 1 - E)
};

// Which side the bounded form's area coverage counts (docs/decisions/gmatch.md §3).
// How the prefilter ranks the models before the full search (docs/decisions/gmatch.md §9).
enum class PrefilterBy {
  kCoarse,   // the same search on the object's few largest segments only (coarse_segments)
  kSummary,  // summary_distance of the graph summaries (footprint, area, normal tilt)
};

enum class Coverage {
  kBoth,   // sqrt(model side x object side): a small model cannot cover part of a big object
  kModel,  // matched model area / area of the model's X largest segments (before issue 15)
};

struct Params {
  int max_segments = 15;               // X: object segments considered (largest area first)
  int branches = 5;                    // B: best branches recursed on per tree node
  double area_factor = 1.0;            // f_a (Eq. 6.4): 100 f_a % area change = one distance unit
  double thickness_weight = 10;        // w_t (Eq. 6.5)
  double elongation_weight = 1;        // w_e (Eq. 6.6)
  double unary_threshold = 0.6;        // prune a branch when E_U > this
  double orientation_threshold = 0.3;  // prune when any pairwise E_O > this
  double distance_threshold = 0.3;     // prune when any pairwise d_R > this
  double exp_unary = 1, exp_orientation = 1, exp_distance = 1, exp_area = 1;  // e_u..e_a
  OrientationForm orientation = OrientationForm::kRelative;
  NormalSign normals = NormalSign::kAxial;
  ErrorForm error = ErrorForm::kBounded;
  Coverage coverage = Coverage::kBoth;
  // Branch and bound (bounded form only): skip a subtree whose score upper bound cannot beat
  // the best complete match found so far. It never changes the result, only the time.
  bool bound = true;
  // Tree nodes expanded per model before the search stops with the best match so far
  // (0 = unlimited). A safety valve against exponential blow-up.
  std::int64_t max_nodes = 0;
  // Prefilter (docs/decisions/gmatch.md §9): rank the models cheaply and run the full search on
  // the K best only (0 = off: every model). With K >= the number of models the result is
  // identical to off.
  int prefilter = 0;
  PrefilterBy prefilter_by = PrefilterBy::kCoarse;
  int coarse_segments = 5;  // kCoarse: object segments (largest first) the coarse search uses
  // Worker threads: models are searched (and coarse-ranked) in parallel (common::parallel_for);
  // the result does not depend on the count.
  int threads = 1;
};

// Throws common::UsageError naming the option (--max-segments, ...) of the first parameter out
// of its range.
void validate(const Params& params);

// Throws common::DataError(name, ...) when a graph cannot be matched: no segments, duplicate
// segment ids, non-finite or non-positive areas, thickness/elongation outside [0, 1],
// zero or non-finite normals, non-finite centroids.
void validate_graph(const documents::SegmentGraph& graph, const std::string& name);

struct Model {
  std::string name;  // file stem
  documents::SegmentGraph graph;
};

struct SearchStats {
  std::int64_t nodes = 0;   // tree nodes expanded (children evaluated)
  std::int64_t leaves = 0;  // complete assignments scored
  bool truncated = false;   // max_nodes reached
};

// Matches one object graph against one model graph. The returned ModelScore has rank 0
// (ranks are assigned by run()). Pairs are listed in match order (object area, largest first).
documents::ModelScore match_model(const documents::SegmentGraph& object, const Model& model,
                                  const Params& params, SearchStats* stats = nullptr);

// Entropy in bits of scores normalised to a distribution (Eq. 6.14-6.15): 0 when one score
// is non-zero, log2 N when all N are equal (including all zero: no information at all).
double entropy(const std::vector<double>& scores);

// Cheap, heading-invariant summary of a graph's X largest segments (the ones the search
// considers): their total area, the area-weighted spread of their centroids along the two
// horizontal principal axes and the vertical, and the share of their area by normal tilt.
struct Summary {
  int segments = 0;                // segments summarised (min(X, count))
  double area = 0;                 // m^2
  std::array<double, 3> spread{};  // m: horizontal major, horizontal minor, vertical
  std::array<double, 3> tilt{};    // area share with |n_z| < 0.38, < 0.92, >= 0.92
};
Summary summarize(const documents::SegmentGraph& graph, int max_segments);
// Distance between two summaries: |log area ratio| + sum of |log spread ratios| (spreads
// floored at 5 cm) + L1 distance of the tilt shares. Symmetric, 0 for equal summaries.
double summary_distance(const Summary& a, const Summary& b);
// Indices of the params.prefilter best models, in modelbase order: kCoarse, the highest scores
// of the search with X = min(coarse_segments, max_segments); kSummary, the nearest by
// summary_distance of the X-largest-segment summaries. Ties: modelbase order. prefilter <= 0
// or >= models.size(): every index. Models are ranked on params.threads threads (the result
// does not depend on the thread count).
std::vector<int> prefilter(const documents::SegmentGraph& object, const std::vector<Model>& models,
                           const Params& params);

struct Inputs {
  const documents::SegmentGraph* object = nullptr;
  const std::vector<Model>* models = nullptr;
};

struct Outputs {
  documents::MatchResult result;   // models ranked, entropy, error_form (no provenance)
  std::vector<SearchStats> stats;  // per model, in modelbase order (0 when not searched)
  int searched = 0;                // models kept by the prefilter (all when it is off)
};

// Matches the object against every model kept by the prefilter (all when params.prefilter is
// 0 or >= the number of models; only the kept models are ranked and listed), models on
// params.threads threads (the result does not depend on the count), ranks by score (ties: model
// name), computes entropy. Neither parses options nor writes anything.
Outputs run(const Params& params, const Inputs& inputs);

// Largest model graph read_modelbase() accepts (2 000² pairs × 16 bytes = 64 MB of tables).
inline constexpr std::size_t kMaxModelSegments = 2000;

// Reads every "<model>.json" in `dir`, sorted by file name; other entries are ignored.
// Throws DataError naming the directory (missing, not a directory, no models) or the file
// (malformed, rejected by validate_graph, or over kMaxModelSegments segments).
std::vector<Model> read_modelbase(const std::string& dir);

const char* to_string(OrientationForm form);
const char* to_string(NormalSign sign);
const char* to_string(ErrorForm form);
const char* to_string(Coverage coverage);
const char* to_string(PrefilterBy by);

// Display name of the object: the file stem, or for the experiment's generic names
// (segments.json, match.json) the directory holding them ("out/sedan/circle/noise-8").
std::string object_name(const std::string& path);
// One line per model (rank, model, score, margin over the next, error terms, matched and
// considered object segments) under two '#' header lines.
std::string format_table(const documents::MatchResult& result, const std::string& object);

}  // namespace canopy::gmatch
