// fitvox: local surface fits in cubic voxels (thesis ch. 3, spec PIPELINE.md §4).
//
// The points are partitioned into cubic voxels of edge h = `voxel` on a fixed grid whose voxel
// centres are the points (i h, j h, k h): voxel (i, j, k) = [(i-1/2) h, (i+1/2) h) x ... ,
// i = floor(x / h + 1/2). Every point belongs to exactly one neighbourhood, the result does not
// depend on the cloud's bounding box, and the ground plane z = 0 lies mid-layer. Per voxel: PCA frame (u, v,
// w = largest, middle, smallest eigenvector, right-handed), least-squares biquadratic w = a0 u² + a1 uv + a2
// v² + a3 u + a4 v + a5 in coordinates about the sample point p (the input point nearest the voxel centre),
// RMS residual along w. A voxel is kept when it has at least `min_points` points, its points determine the
// fit and its RMS is within the bound (see Params). Samples come out sorted by voxel (i, j, k).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "canopy/formats/point_cloud.h"

namespace canopy::fitvox {

// The largest --support in voxel edges: auto is 0.5-1, and the cost per sample grows with its
// square (docs/decisions/hardening.md, stop 71).
inline constexpr double kMaxSupport = 4.0;
// The range of --support in words, "(0, 4]" (kMaxSupport), for its messages.
std::string support_range();

struct Params {
  double voxel = 0.128;    // voxel edge (m), > 0
  int min_points = 32;     // fewer points in a voxel -> rejected (>= 6)
  double max_rms = 0.008;  // RMS bound for noiseless data (m): the model-error tolerance
  // Noise level used to widen the RMS bound (m): < 0 = estimate it from the scan's own fits
  // (median unbiased residual over all voxels with enough points), 0 = the fixed thesis bound
  // max_rms, > 0 = this known sigma. With sigma, a voxel of k points is kept when
  //   rms² <= max_rms² + sigma² (k-6)/k (1 + noise_margin sqrt(2/(k-6)))
  // i.e. the thesis tolerance plus the expected noise contribution to the RMS and
  // `noise_margin` standard deviations of its chi-square sampling spread.
  double noise = -1.0;
  double noise_margin = 3.0;
  // Resampling of the kept voxels (docs/decisions/noise.md). true: the sample is the voxel's
  // input point nearest its centre (`from_centroid`: the centroid of its points) moved onto a
  // surface refitted to every scan point within the support radius of it (two moving-least-
  // squares steps: fit about the start point, project along w, fit again about the projected
  // point, which carries the frame, coefficients and normal; rms and variation stay the
  // voxel's own), and of samples closer than `merge` x voxel the one with more points is kept.
  // Voxel faces no longer truncate the noise, so a surface lying near a face no longer yields
  // two parallel layers of samples. false = the thesis: the input point nearest the voxel
  // centre, fitted with its voxel's points only.
  // support < 0 = auto: the ball just holds ±3 sigma of the noise, clamp(6 sigma / voxel, 0.5, 1)
  // voxel edges (sigma = the noise level used for the RMS bound, estimated or given).
  bool resample = true;
  bool from_centroid = false;  // start from the voxel's point centroid (false: its point nearest the centre)
  double support = -1.0;
  double merge = 0.25;
  int threads = 1;        // worker threads for the per-voxel fits (output identical for any count)
  bool keep_all = false;  // run() fills Result::all too (every voxel with its verdict)
};

// Throws common::UsageError naming the option (--voxel, ...) of the first parameter out of
// its range: voxel [1 mm, 100 m], min_points >= 6, max_rms [0, 100 m], noise < 0 (auto) or
// [0, 100 m], noise_margin [0, 1e6], support != 0, merge >= 0, threads >= 1.
void validate(const Params& params);

// Input: a scan. `sensor` (unit vectors from each point toward the sensor that saw it) and
// `labels` are optional (empty) or have one entry per point.
struct Scan {
  std::vector<Eigen::Vector3d> points;  // m, world frame; finite
  std::vector<Eigen::Vector3d> sensor;  // unit; empty = orient normals toward +z
  std::vector<std::uint32_t> labels;    // ground truth; empty = all unknown (0)
};

// kMerged: kept, but its resampled point lies within Params::merge of a sample with more points.
enum class Verdict { kKept, kTooFew, kDegenerate, kTooRough, kMerged };

// The fit of one neighbourhood about its sample point p.
struct Fit {
  Verdict verdict = Verdict::kDegenerate;  // kKept here only means "fitted"
  bool plane_fallback = false;             // biquadratic undetermined (rank < 6): plane fit, a0=a1=a2=0
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // of the biquadratic at p, toward sensor
  Eigen::Vector3d u = Eigen::Vector3d::UnitX(), v = Eigen::Vector3d::UnitY(),
                  w = Eigen::Vector3d::UnitZ();  // right-handed; w flipped with the normal
  std::array<double, 6> a{};                     // coefficients in (u, v, w) about p (1/m, -, 1/m, -, -, m)
  double rms = 0;                                // m
  double variation = 0;                          // lambda_min / (sum of eigenvalues)
  double mean_curvature = 0;                     // 1/m, > 0 when the surface bends toward the normal
  double gauss_curvature = 0;                    // 1/m²
};

// Fits the points (world frame, m) about points[p_index]; the normal and frame are oriented
// so that normal · toward >= 0. Never returns NaN: undetermined fits give kDegenerate (fewer
// than 3 points, coincident or collinear points) or plane_fallback.
Fit fit_neighbourhood(const std::vector<Eigen::Vector3d>& points, std::size_t p_index,
                      const Eigen::Vector3d& toward);
// The same fit about an arbitrary origin p (not necessarily one of the points).
Fit fit_about(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& p,
              const Eigen::Vector3d& toward);

struct Sample {
  Fit fit;
  std::array<std::int32_t, 3> voxel{};  // grid index (i, j, k)
  std::size_t source_index = 0;         // row of p in the input scan
  std::uint32_t point_count = 0;
  std::uint32_t label = 0;  // majority label (ties: smallest label value)
  double label_purity = 1.0;
  Eigen::Vector3d sensor = Eigen::Vector3d::UnitZ();  // of p (or +z)
};

struct Stats {
  std::size_t points = 0, voxels = 0;
  std::size_t too_few = 0, degenerate = 0, too_rough = 0, kept = 0, plane_fallback = 0;
  std::size_t merged = 0;              // kept voxels whose resampled point merged into another sample
  double sigma = 0;                    // noise level used to widen the bound (estimated or given), m
  double sigma_estimated = 0;          // the scan's own estimate (m), computed even when not used
  double support = 0;                  // resampling support radius used (m); 0 = no resampling
  double rms_bound_at_max_points = 0;  // RMS bound for the most populated voxel (m)
  double rms_bound_at_min_points = 0;  // RMS bound for a voxel of min_points points (m)
  // The least and greatest RMS bound over the point counts min_points..the most populated
  // voxel's (m). Not monotone in k: --max-rms at 6 points (a biquadratic fits 6 points exactly,
  // no noise term), rising to a peak (near 24 points at --noise-margin 3), then falling toward
  // sqrt(max_rms² + sigma²).
  double rms_bound_least = 0, rms_bound_greatest = 0;
  std::size_t max_points = 0;  // points of the most populated voxel (at least min_points)
};

struct Result {
  std::vector<Sample> samples;  // kept voxels sorted by (i, j, k)
  // Every voxel with its verdict (same order), filled when Params::keep_all is set.
  std::vector<Sample> all;
  Stats stats;
};

using Inputs = Scan;
using Outputs = Result;

// Throws common::UsageError on invalid parameters (validate()), common::Error on non-finite
// coordinates, mismatched optional columns, or a voxel index that does not fit (coordinate / voxel beyond
// ±2^31, or a grid extent of more than 2^63 voxels): never silently wrong.
Outputs run(const Params& params, const Inputs& inputs);

// RMS bound for a voxel of k points at noise level sigma (see Params).
double rms_bound(const Params& params, double sigma, std::size_t k);
// The least and greatest rms_bound over k = k_min..k_max (k_min <= k_max).
std::pair<double, double> rms_bound_range(const Params& params, double sigma, std::size_t k_min,
                                          std::size_t k_max);

// Conversions from / to the on-disk contract (formats/README.md "Scan" and "Samples").
// scan_from_cloud: requires x y z (DataError naming `name`); sensor_* all or none (missing ->
// scan.sensor empty); label optional. `has_sensor` reports which.
Scan scan_from_cloud(const formats::PointCloud& cloud, const std::string& name, bool* has_sensor);
formats::PointCloud samples_to_cloud(const Result& result);

}  // namespace canopy::fitvox
