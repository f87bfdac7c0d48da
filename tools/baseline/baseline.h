// baseline: a recogniser built from PCL's descriptors (issue 17), run on the same inputs as
// canopy (a candidate's points; the modelbase's <model>.pcd surfaces) so that canopy's
// numbers have something to stand beside.
//
//   global: VFH (Rusu et al. 2010; viewpoint straight above: heading-invariant) of the candidate
//           against the VFH of each model seen from a ring of sensor positions (back-face
//           culled views) plus the whole surface; nearest neighbour (L1 on the normalised
//           histograms) per model. (PCL's ESF reseeds rand() from the clock: not repeatable.)
//   local:  FPFH (Rusu et al. 2009) correspondences, RANSAC with pre-rejection
//           (pcl::SampleConsensusPrerejective, the SAC-IA successor), then ICP, both estimating
//           a ground pose (x, y, heading: PCL's TransformationEstimation2D); ranked by the
//           fitness sqrt(share of candidate points on the posed model x share of model points
//           on the candidate).
//
// Frames: as verify's (docs/decisions/verify.md): the model's is the modelbase's (ground z = 0,
// heading 0), the candidate's is its points' frame (ground z = 0). A pose maps model
// coordinates to candidate coordinates. Decisions and parameters: docs/decisions/baseline.md.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "canopy/documents/match_result.h"
#include "canopy/formats/point_cloud.h"
#include "canopy/documents/verdict.h"

namespace canopy::baseline {

// Upper bounds of the iteration and view counts (validate): 25, 17 and 8 times the defaults.
inline constexpr int kMaxRansacIterations = 100000;
inline constexpr int kMaxIcpIterations = 500;
inline constexpr int kMaxViews = 64;

struct Params {
  double min_height = 0.3;       // candidate points below this z are ground (m; cocone's cut)
  double voxel = 0.2;            // downsampling leaf before the local descriptors (m)
  double normal_radius = 0.4;    // PCL normal estimation radius of the downsampled clouds (m)
  double feature_radius = 0.75;  // FPFH radius (m)
  double inlier = 0.25;          // RANSAC inlier / fitness distance (m)
  int ransac_iterations = 4000;  // RANSAC iterations per model
  int icp_iterations = 30;       // ICP iterations per model (0 = none)
  int views = 8;                 // VFH model views on the ring (plus the whole surface)
  double view_elevation = 75 * 0.017453292519943295;  // the ring's elevation (rad; 75 deg)
  unsigned seed = 1;                                  // RANSAC's random draws
  // The "none" rule of a verdict (--verdict): the method's best model is the answer when its
  // score reaches this, else none. Fixed on development tiles (docs/decisions/baseline.md §4).
  double accept_vfh = 0.68;
  double accept_fpfh = 0.35;
  std::string methods = "both";  // the methods run: "vfh", "fpfh" or "both"
};

void validate(const Params& params);  // throws common::UsageError

struct Cloud {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;  // unit; empty when unknown
};

// Candidate: every row at or above min_height (no labels are used: they are ground truth).
Cloud candidate_from_cloud(const formats::PointCloud& cloud, const std::string& name, double min_height);
// Model surface: label-1 rows when a label field carries labels (formats::carries_labels: not 0
// everywhere), else rows above 5 cm; normals required.
Cloud model_from_cloud(const formats::PointCloud& cloud, const std::string& name);

struct Model {
  std::string name;
  Cloud surface;
};

// The <model>.pcd files of `dir` as (model name, path), sorted by name: what read_modelbase
// reads. DataError naming the directory when it is missing, unlistable or holds none.
std::vector<std::pair<std::string, std::string>> list_modelbase(const std::string& dir);
// Reads every <model>.pcd of `dir`, sorted by name. DataError naming the directory or file.
std::vector<Model> read_modelbase(const std::string& dir);

// The models' side of both methods (issue 31; docs/decisions/baseline.md §7): what run()
// computes from each model's surface alone, the same for every candidate. prepare_models
// computes it (run() does so itself when Inputs::prepared is null); `baseline --prepare`
// writes it once per modelbase and `--model-cache` reads it back bit for bit (model_cache.h).
struct PreparedModel {
  std::string name;
  // vfh: per view (the ring's, then the whole surface) whether it has >= 3 points, and its
  // normalised VFH (zeros when it has not).
  std::vector<std::uint8_t> seen;
  std::vector<std::array<float, 308>> vfh;
  // fpfh: the downsampled surface with PCL's normals, as PCL's PointNormal fields (x, y, z, 1,
  // normal x, y, z, 0, curvature), and its FPFH (33 per point; none when fewer than 3 points;
  // features_dense = PCL's is_dense of the feature cloud).
  std::vector<std::array<float, 9>> points;
  std::vector<std::array<float, 33>> features;
  bool features_dense = true;
};

struct PreparedModels {
  bool vfh = false, fpfh = false;  // which methods' sides it holds
  std::vector<PreparedModel> models;
};

// The models' side of the methods asked for (vfh, fpfh), models in the given order.
PreparedModels prepare_models(const std::vector<Model>& models, const Params& params, bool vfh, bool fpfh);

struct Entry {
  std::string model;
  int rank = 0;
  double score = 0;     // larger is better, in [0, 1]
  double distance = 0;  // global (vfh): L1 histogram distance of the nearest view, in [0, 2]
  double fitness = 0;   // local: as score; the two shares follow
  double candidate_share = 0, model_share = 0;
  int view = -1;                                       // global: the nearest view (views = the whole surface)
  bool posed = false;                                  // local: pose found
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();  // model -> candidate
};

struct Ranking {
  std::string method;         // "vfh" or "fpfh"
  std::vector<Entry> models;  // ranked (score, then model name)
  double seconds = 0;         // wall time of the method (logged, not serialised)
};

struct Result {
  std::vector<Ranking> methods;
  int candidate_points = 0;
};

struct Inputs {
  const Cloud* candidate = nullptr;
  const std::vector<Model>* models = nullptr;  // unused when `prepared` is given
  // The models' side, prepared with the same parameters (else computed from `models`).
  const PreparedModels* prepared = nullptr;
};

using Outputs = Result;

// Runs both methods (or the one params.methods names: "vfh", "fpfh", "both").
Outputs run(const Params& params, const Inputs& inputs);

// canopy.baseline v1 JSON (documents/baseline_ranking.h, formats/README.md). No times: same inputs, same
// bytes (the experiment graph records each run's wall time beside it).
std::string serialize(const Result& result, const std::string& object,
                      const std::vector<std::pair<std::string, std::string>>& parameters,
                      const std::vector<std::string>& inputs);

// One method's answer per candidate as a canopy.verdict v1 (formats/README.md), so that the
// tile workflow's collect and score read it as they read verify's: the best model when its
// score reaches `accept`, else none (model null). Hypotheses = the method's ranking (rank in
// gmatch_rank, score in gmatch_score and score, start = the method's name); confidence = the
// best score for a model, 1 - the best score for none (an uncalibrated score, not verify's
// probability). Pose: fpfh's ground pose (model -> candidate); vfh has none, so its hypotheses
// carry the identity, i.e. the candidate frame of detect (footprint centre on the ground, x
// along the footprint's long axis): a position without a heading of its own.
// explained = fpfh's candidate share (0 for vfh); fit_rms and free_space_violation are not
// computed (0).
documents::Verdict to_verdict(const Ranking& ranking, double accept, const std::string& candidate,
                              const formats::Provenance& provenance);

// One method's ranking as a canopy.match_result (`baseline --hypotheses`, issue 29: "FPFH poses
// scored by verify"), the document verify reads: every model in the ranking's order (rank 1 =
// the model to_verdict answers), score = the method's score, the error terms 0, no segment
// pairs, and pose = the method's pose (model -> candidate, the frame of verify's poses) when it
// found one (fpfh: RANSAC converged), else none. object = the candidate's points as given;
// error_form = the method's name; entropy = documents::match_entropy of the scores.
documents::MatchResult to_match_result(const Ranking& ranking, const std::string& candidate,
                                       const formats::Provenance& provenance);

}  // namespace canopy::baseline
