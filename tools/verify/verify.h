// verify: checks gmatch's top hypotheses against the candidate's points (the thesis's future
// work 5, issue 15). For each of the top-k models: a rigid pose from the matched segment pairs
// (heading + translation; the 180-degree flip and a principal-axis start tried explicitly) or,
// when the match result gives the model a pose (baseline --hypotheses), that pose instead,
// refined by PCL point-to-plane ICP (6 DOF, so slopes give pitch/roll); then a two-sided score:
//   explained  = share of the candidate's points (above the ground cut) lying on the posed
//                model's surface (point-to-plane distance <= inlier distance);
//   violation  = share of the posed model's surface that the sensor should have seen (facing
//                a sensor direction recorded in the scan, no scan point in front of it along
//                that ray) but where the scan has no point: free-space violation.
// score = explained * (1 - violation); the best hypothesis is answered when its score passes
// the acceptance threshold, else "none"; confidence = logistic calibration of the score and
// its margin over the next model (docs/decisions/verify.md).
//
// Frames: the model's frame is the modelbase's (ground z = 0, heading 0); the candidate's is
// its points' frame (ground z = 0). A pose maps model coordinates to candidate coordinates.
// The logic does no I/O except read_models().
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

#include "canopy/common/math.h"
#include "canopy/documents/match_result.h"
#include "canopy/formats/point_cloud.h"
#include "canopy/documents/segment_graph.h"
#include "canopy/documents/verdict.h"

namespace canopy::verify {

// Upper bound of Params::icp_iterations (25 times the default; validate).
inline constexpr int kMaxIcpIterations = 500;

struct Params {
  // gmatch hypotheses checked (rank 1..k): 5 since stop 65 (docs/decisions/verify.md §21), the
  // value of share/params/verify.ini; the built-in default stayed 3 until stop 67, so the shell,
  // which names no --config, checked fewer than make (docs/decisions/hardening.md).
  int top_k = 5;
  double min_height = 0.3;       // candidate points below this z are ground (m; cocone's cut)
  double inlier_distance = 0.1;  // point-to-plane distance counted as "on the surface" (m)
  double inlier_radius = 0.25;   // and at most this far from the nearest model sample (m)
  // The free-space test's "seen" (a candidate point on an expected-visible model sample) looks
  // within max(inlier_radius, seen_spacing x s) of the model sample, s = the candidate's own
  // point spacing (median nearest-neighbour distance of its points above min_height,
  // sample_spacing): a candidate sampled more coarsely than inlier_radius (the density rule's
  // fitvox voxels of 250-350 mm at 50-100 object points/m²) leaves model surface between its
  // samples that no point is near, which is not free space (docs/decisions/verify.md §17).
  // 0 = off: inlier_radius alone, the test before (the ablation, beside the rule on the density
  // ladder: mk/density.mk DENSITY_VERIFY_ABLATION). The explained test (candidate point -> model
  // sample, 128 mm) is not touched.
  double seen_spacing = 1.0;
  double facing = 0.5;             // model surface counts for a view when n.s >= this
  double ray_cell = 0.2;           // cell of the per-view depth buffers (m)
  double occlusion_margin = 0.15;  // a scan point this much nearer the sensor hides (m)
  // Free space: "unseen" charges expected-visible model surface with no scan point on it;
  // "through" charges it only where the view's depth-buffer cell holds a scan point (the ray
  // demonstrably reached that depth: ground or surface seen at or behind it), so surface
  // whose cell is empty (occluders cropped away, no return) is not evidence either way.
  bool free_space_through = false;
  double icp_coarse = 0.5;  // ICP max correspondence distance, first stage (m)
  double icp_fine = 0.2;    // second stage (m)
  int icp_iterations = 20;  // per stage
  int icp_points = 1000;    // candidate points ICP uses at most (even stride)
  bool flip = true;         // try the 180-degree heading flip of every start
  // A parked vehicle stands upright: a pose whose model vertical leans more than this from the
  // tile's vertical (the candidate's without a transform) is not a vehicle's (on its side, on its
  // nose, upside down); a hypothesis no start of which poses upright scores 0 and is marked
  // tilted (docs/decisions/verify.md §21). 180 degrees: no bound.
  double max_tilt = 40 * common::kPi / 180;  // radians
  double accept = 0.556;                     // answer "none" when the best score is below this
  // The null hypothesis (docs/decisions/verify.md §14): a plain box of the candidate's own
  // extent (top and four sides down to the ground), posed by its principal axes, refined by
  // ICP and scored like a model. The best model is answered only when its score beats the
  // box's by at least box_margin: a model that explains the candidate no better than a box of
  // its size gives no evidence of a vehicle (a container, a caravan, a trailer). box = false
  // checks no box (the verdict has no "box"; the decision as before).
  bool box = true;
  double box_margin = 0.0;
  // confidence = 1 / (1 + exp(-(c0 + c_score * score + c_margin * margin)))
  double conf_bias = -3.548, conf_score = 0.132, conf_margin = 6.874;
  // plus conf_box * (score - the box's score) (0 without a box). Fitted on tile candidates
  // (docs/decisions/verify.md §15); before: accept 0.544, -5.365 6.317 5.573, no box term.
  double conf_box = 3.044;
  // none's confidence = 1 - 1 / (1 + exp(-(none_bias + none_score * score + none_margin *
  // margin + none_box * (score - box score)))): the probability that no vehicle stands at the
  // candidate (what the scene score's reliability of none judges). With the none_ weights equal
  // to the conf_ ones it is 1 - the model's probability (before issue 29's fit on tiles).
  double none_bias = 0.059, none_score = -0.364, none_margin = 1.018, none_box = 5.177;
};

// Throws common::UsageError when a parameter is out of range.
void validate(const Params& params);

// A point set with unit normals (m, frame of its owner).
struct Surface {
  std::vector<Eigen::Vector3d> points, normals;
};

// The candidate: its points with normals and per-point unit directions toward the sensor.
struct Candidate {
  std::vector<Eigen::Vector3d> points, normals, sensor;
};

// A modelbase entry: the segment graph and the surface samples with normals (model frame).
struct Model {
  std::string name;
  documents::SegmentGraph graph;
  Surface surface;
  std::string vehicle_class;  // from <name>.class when the modelbase has one, else ""
};

// Candidate from a samples PCD: requires x y z, normal_x/y/z and sensor_x/y/z (DataError
// naming `name` otherwise), non-empty.
// `sensor` (one unit vector per point, e.g. formats::sensor_directions') replaces the
// sensor_x/y/z columns, which are then not needed.
Candidate candidate_from_cloud(const formats::PointCloud& cloud, const std::string& name,
                               const std::vector<Eigen::Vector3d>* sensor = nullptr);
// Model surface from a samples PCD (model frame: ground z = 0); normals required. The rows kept:
// - a label field with some label other than 0 (a labelled render: rangetrace's 1 target,
//   2 foliage, 3 ground; formats/labels.h): the label-1 (target) rows;
// - no label field, or one that is 0 (unknown) on every row, as fitvox writes for an input
//   without labels (a tile candidate's samples): the rows above `min_z`.
// No row kept is a DataError naming `name`. `zero_labels`, when given, is set to whether the
// surface had a label field of 0 only (read_models says so once on stderr).
inline constexpr double kSurfaceMinZ = 0.05;  // m: the ground cut of a surface without labels
Surface surface_from_cloud(const formats::PointCloud& cloud, const std::string& name,
                           double min_z = kSurfaceMinZ, bool* zero_labels = nullptr);

// Reads <dir>/<name>.json and <dir>/<name>.pcd for every name (DataError naming `who` when a
// model is not in the modelbase, naming the file when a file is malformed), and the class in
// <dir>/<name>.class when that file exists (one word on one line; DataError otherwise).
// Surfaces whose label field is 0 everywhere (surface_from_cloud) are named in one info line.
std::vector<Model> read_models(const std::string& dir, const std::vector<std::string>& names,
                               const std::string& who);

// One hypothesis checked at one pose.
struct Check {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // model -> candidate
  double explained = 0, violation = 1, score = 0, fit_rms = 0;
  int inliers = 0, expected = 0;
};

// Scores a posed model against the candidate (exposed for tests).
class Scorer {
 public:
  Scorer(const Candidate& candidate, const Params& params);
  Check score(const Surface& model, const Eigen::Isometry3d& pose) const;
  std::size_t views() const { return views_.size(); }
  std::size_t above_ground() const { return above_.size(); }
  // The radius of the free-space test's "seen" (Params::seen_spacing) for this candidate (m).
  double seen_radius() const { return seen_radius_; }
  const std::vector<Eigen::Vector3d>& above_points() const { return above_; }

 private:
  struct Impl;
  const Candidate& c_;
  Params p_;
  std::vector<Eigen::Vector3d> above_;
  std::vector<Eigen::Vector3d> views_;
  double seen_radius_ = 0;
  std::shared_ptr<Impl> impl_;
};

// The point spacing of a point set: the median distance from each point to its nearest other
// point (m); 0 with fewer than two points.
double sample_spacing(const std::vector<Eigen::Vector3d>& points);

// The null hypothesis's surface and start pose: a box over the candidate's points above the
// ground cut, its axes their horizontal principal axes, its extent their 1st-99th percentiles
// along them and from the ground (z = 0) to the 99th percentile of z; samples every `spacing`
// on the top and the four sides with outward normals, in the box's own frame (ground z = 0,
// centred), and `pose` box -> candidate. False (nothing set) with fewer than 10 points.
bool null_box(const std::vector<Eigen::Vector3d>& above, double spacing, Surface* box, Eigen::Isometry3d* pose);

// Refines a pose with point-to-plane ICP (candidate points above ground onto the model).
Eigen::Isometry3d refine(const Surface& model, const std::vector<Eigen::Vector3d>& candidate,
                         const Eigen::Isometry3d& start, const Params& params);

// Heading + translation start from matched segment pairs (area-weighted 2-D Procrustes on the
// centroids); false when fewer than two pairs are matched.
bool pose_from_pairs(const documents::SegmentGraph& object, const documents::SegmentGraph& model,
                     const std::vector<documents::SegmentPair>& pairs, Eigen::Isometry3d* pose);
// Heading + translation start aligning the horizontal principal axes and centroids.
Eigen::Isometry3d pose_from_axes(const std::vector<Eigen::Vector3d>& candidate,
                                 const std::vector<Eigen::Vector3d>& model);

// Inputs that belong together (docs/decisions/verify.md): each check throws common::DataError
// naming the files when they provably describe different candidates.
// The match's pairs name segments of the graph, each at most once, and the largest: no segment
// left out is larger than a paired one (gmatch pairs the X largest object segments).
void check_match_names_graph(const documents::MatchResult& match, const std::string& match_name,
                             const documents::SegmentGraph& graph, const std::string& graph_name);
// The graph was made from a mesh of these points (cocone keeps a subset of the sample rows, ncut
// partitions the mesh's vertices): every vertex index below the number of points, no more
// vertices in all segments than points, every centroid (a mean over mesh triangles) inside the
// points' bounding box.
void check_graph_on_points(const documents::SegmentGraph& graph, const std::string& graph_name,
                           const std::vector<Eigen::Vector3d>& points, const std::string& points_name);
// Every vertex of the graph's mesh is exactly one of the points.
void check_mesh_on_points(const std::vector<Eigen::Vector3d>& mesh, const std::string& mesh_name,
                          const std::string& graph_name, const std::vector<Eigen::Vector3d>& points,
                          const std::string& points_name);

struct BelongInputs {
  const documents::MatchResult* match = nullptr;
  std::string match_path;  // as given ("-" = stdin)
  // Null for a match result without pairs read without --segments (baseline --hypotheses):
  // then only its "object" is checked, against the points (the file its poses are in).
  const documents::SegmentGraph* segments = nullptr;
  std::string segments_path;
  const Candidate* candidate = nullptr;
  std::string points_path;
};
// All of the above, and the names the documents record, where they resolve (beside the
// recording document, or from the working directory): the match's "object" must be the
// --segments file (or one with the same bytes); the graph's "mesh", when it is a readable PLY
// with as many vertices as the segments hold, goes through check_mesh_on_points. Names that do
// not resolve prove nothing and are passed over.
void check_inputs_belong(const BelongInputs& in);

struct Inputs {
  const Candidate* candidate = nullptr;
  const documents::SegmentGraph* segments = nullptr;  // an empty graph when the match has no pairs
  const documents::MatchResult* match = nullptr;
  const std::vector<Model>* models = nullptr;  // at least the top-k hypotheses' models
  const Eigen::Isometry3d* to_tile = nullptr;  // candidate frame -> tile frame; null = none
};

using Outputs = documents::Verdict;

// Checks the top-k hypotheses and decides. Fills every field of the verdict but provenance
// and inputs; the tile pose (transform, pose_tile) when `to_tile` is given.
Outputs run(const Params& params, const Inputs& inputs);

}  // namespace canopy::verify
