#include "fitvox/fitvox.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>
#include <utility>

#include "canopy/common/error.h"
#include "canopy/common/parallel.h"
#include "canopy/formats/cloud_eigen.h"

namespace canopy::fitvox {
namespace {

using Eigen::Vector3d;
using common::Error;

// Relative thresholds: PCA spread below kCollinear * largest spread counts as zero (points on
// a line or a single point); QR pivots below kRankThreshold * largest pivot count as zero.
// Both act on coordinates scaled to [-1, 1], so they are independent of units and voxel size.
constexpr double kCollinear = 1e-9;
constexpr double kRankThreshold = 1e-9;

bool all_finite(const Fit& f) {
  bool ok = f.normal.allFinite() && f.u.allFinite() && f.v.allFinite() && f.w.allFinite() &&
            std::isfinite(f.rms) && std::isfinite(f.variation) && std::isfinite(f.mean_curvature) &&
            std::isfinite(f.gauss_curvature);
  for (double c : f.a) ok = ok && std::isfinite(c);
  return ok;
}

std::string fmt(const char* format, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

}  // namespace

Fit fit_neighbourhood(const std::vector<Vector3d>& points, std::size_t p_index, const Vector3d& toward) {
  if (p_index >= points.size()) return Fit{};
  return fit_about(points, points[p_index], toward);
}

namespace {

// PCA frame of the points about p (u, v, w = largest, middle, smallest axis, right-handed) and
// the surface variation; false when the points are coincident or collinear.
bool pca_frame(const std::vector<Vector3d>& points, Fit& f) {
  const std::size_t k = points.size();
  // Everything relative to p: keeps the digits when coordinates are large.
  Vector3d mean = Vector3d::Zero();
  for (const Vector3d& q : points) mean += q - f.p;
  mean /= static_cast<double>(k);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vector3d& q : points) {
    const Vector3d d = q - f.p - mean;
    cov.noalias() += d * d.transpose();
  }
  cov /= static_cast<double>(k);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  if (es.info() != Eigen::Success) return false;
  const Vector3d ev = es.eigenvalues();                             // ascending
  if (!(ev(2) > 0) || !(ev(1) > kCollinear * ev(2))) return false;  // coincident or collinear
  f.u = es.eigenvectors().col(2).normalized();
  f.v = es.eigenvectors().col(1).normalized();
  f.w = f.u.cross(f.v).normalized();
  const double lambda_min = std::max(ev(0), 0.0);
  f.variation = lambda_min / (lambda_min + ev(1) + ev(2));
  return true;
}

// Least-squares w = a0 u² + a1 uv + a2 v² + a3 u + a4 v + a5 in the scaled coordinates t
// (|u|, |v| <= 1); a plane (a0 = a1 = a2 = 0, plane_fallback) when the biquadratic is
// undetermined; false when the plane is too.
bool solve_coefficients(const Eigen::Matrix<double, Eigen::Dynamic, 3>& t, std::array<double, 6>& a, Fit& f) {
  const auto k = t.rows();
  if (k >= 6) {
    Eigen::Matrix<double, Eigen::Dynamic, 6> m(k, 6);
    for (Eigen::Index i = 0; i < k; ++i) {
      const double u = t(i, 0), v = t(i, 1);
      m.row(i) << u * u, u * v, v * v, u, v, 1.0;
    }
    Eigen::ColPivHouseholderQR<Eigen::Matrix<double, Eigen::Dynamic, 6>> qr(m);
    qr.setThreshold(kRankThreshold);
    if (qr.rank() == 6) {
      const Eigen::Matrix<double, 6, 1> x = qr.solve(t.col(2));
      for (int j = 0; j < 6; ++j) a[j] = x(j);
    } else {
      f.plane_fallback = true;
    }
  } else {
    f.plane_fallback = true;
  }
  if (f.plane_fallback) {
    Eigen::Matrix<double, Eigen::Dynamic, 3> m(k, 3);
    for (Eigen::Index i = 0; i < k; ++i) m.row(i) << t(i, 0), t(i, 1), 1.0;
    Eigen::ColPivHouseholderQR<Eigen::Matrix<double, Eigen::Dynamic, 3>> qr(m);
    qr.setThreshold(kRankThreshold);
    if (qr.rank() < 3) return false;
    const Eigen::Vector3d x = qr.solve(t.col(2));
    a = {0, 0, 0, x(0), x(1), x(2)};
  }
  return true;
}

// Orient: the biquadratic's normal at p is (-f_u, -f_v, 1) in (u, v, w). If it faces away
// from the sensor, turn the frame half a turn about u (v -> -v, w -> -w, still
// right-handed); in the new frame w' = -f(u, -v'), which negates a0, a2, a3, a5. Then the
// normal, coefficients and curvatures of the fit.
void orient_and_finish(std::array<double, 6> a, const Vector3d& toward, Fit& f) {
  Vector3d n = (-a[3] * f.u - a[4] * f.v + f.w).normalized();
  if (n.dot(toward) < 0) {
    f.v = -f.v;
    f.w = -f.w;
    a[0] = -a[0];
    a[2] = -a[2];
    a[3] = -a[3];
    a[5] = -a[5];
    n = -n;
  }
  f.normal = n;
  f.a = a;
  const double g = 1 + a[3] * a[3] + a[4] * a[4];
  f.gauss_curvature = (4 * a[0] * a[2] - a[1] * a[1]) / (g * g);
  f.mean_curvature = ((1 + a[4] * a[4]) * 2 * a[0] - 2 * a[3] * a[4] * a[1] + (1 + a[3] * a[3]) * 2 * a[2]) /
                     (2 * std::pow(g, 1.5));
}

}  // namespace

Fit fit_about(const std::vector<Vector3d>& points, const Vector3d& p, const Vector3d& toward) {
  Fit f;
  f.verdict = Verdict::kDegenerate;
  const std::size_t k = points.size();
  f.p = p;
  if (k < 3) return f;
  if (!pca_frame(points, f)) return f;

  // Local coordinates about p, scaled so that |u|, |v| <= 1 (conditioning of the LSQ).
  Eigen::Matrix<double, Eigen::Dynamic, 3> uvw(k, 3);
  double s = 0;
  for (std::size_t i = 0; i < k; ++i) {
    const Vector3d d = points[i] - f.p;
    uvw(i, 0) = d.dot(f.u);
    uvw(i, 1) = d.dot(f.v);
    uvw(i, 2) = d.dot(f.w);
    s = std::max({s, std::abs(uvw(i, 0)), std::abs(uvw(i, 1))});
  }
  if (!(s > 0)) return f;
  const Eigen::Matrix<double, Eigen::Dynamic, 3> t = uvw / s;
  std::array<double, 6> a{};
  if (!solve_coefficients(t, a, f)) return f;
  // Unscale: w/s = a (u/s)² + ... => quadratic terms / s, linear unchanged, constant * s.
  a[0] /= s;
  a[1] /= s;
  a[2] /= s;
  a[5] *= s;

  double sse = 0;
  for (std::size_t i = 0; i < k; ++i) {
    const double u = uvw(i, 0), v = uvw(i, 1);
    const double r = uvw(i, 2) - (a[0] * u * u + a[1] * u * v + a[2] * v * v + a[3] * u + a[4] * v + a[5]);
    sse += r * r;
  }
  f.rms = std::sqrt(sse / static_cast<double>(k));
  orient_and_finish(a, toward, f);
  if (!all_finite(f)) {
    Fit bad;
    bad.p = f.p;
    return bad;
  }
  f.verdict = Verdict::kKept;
  return f;
}

double rms_bound(const Params& params, double sigma, std::size_t k) {
  if (!(sigma > 0) || k <= 6) return params.max_rms;
  const double dof = static_cast<double>(k - 6);
  const double t = dof / static_cast<double>(k) * (1 + params.noise_margin * std::sqrt(2 / dof));
  return std::sqrt(params.max_rms * params.max_rms + sigma * sigma * t);
}

std::pair<double, double> rms_bound_range(const Params& params, double sigma, std::size_t k_min,
                                          std::size_t k_max) {
  double least = rms_bound(params, sigma, k_min), greatest = least;
  for (std::size_t k = k_min + 1; k <= k_max; ++k) {
    const double b = rms_bound(params, sigma, k);
    least = std::min(least, b);
    greatest = std::max(greatest, b);
  }
  return {least, greatest};
}

namespace {

struct VoxelRun {
  std::uint64_t key;
  std::size_t begin, end;  // range in the sorted order
};

void check_input(const Scan& scan, const Params& params) {
  validate(params);
  const std::size_t n = scan.points.size();
  if (!scan.sensor.empty() && scan.sensor.size() != n) {
    throw Error("sensor directions: " + std::to_string(scan.sensor.size()) + " for " + std::to_string(n) +
                " points");
  }
  if (!scan.labels.empty() && scan.labels.size() != n) {
    throw Error("labels: " + std::to_string(scan.labels.size()) + " for " + std::to_string(n) + " points");
  }
  if (n > std::numeric_limits<std::uint32_t>::max()) throw Error("more than 2^32 points");
}

}  // namespace

std::string support_range() {
  char buf[32];
  std::snprintf(buf, sizeof buf, "(0, %g]", kMaxSupport);
  return buf;
}

void validate(const Params& p) {
  auto need = [](bool ok, const std::string& rule) {
    if (!ok) throw common::UsageError(rule);
  };
  need(p.voxel >= 1e-3 && p.voxel <= 100, "--voxel must be in [1mm, 100m]");
  need(p.min_points >= 6, "--min-points must be >= 6");
  need(p.max_rms >= 0 && p.max_rms <= 100, "--max-rms must be in [0, 100m]");
  need(p.noise < 0 || p.noise <= 100, "--noise must be 'auto' or in [0, 100m]");
  need(p.noise_margin >= 0 && p.noise_margin <= 1e6, "--noise-margin must be in [0, 1e6]");
  need((p.support > 0 && p.support <= kMaxSupport) || p.support < 0,
       "--support must be 'auto' or in " + support_range() + " voxel edges");
  need(p.merge >= 0 && std::isfinite(p.merge), "--merge must be >= 0");
  need(p.threads >= 1, "--threads must be >= 1");
}

namespace {

// The scan's points on the voxel grid: each point's voxel index, the points ordered by
// (voxel, input index), and each occupied voxel's run in that order ((i, j, k) order).
struct Grid {
  std::vector<std::array<std::int32_t, 3>> index;
  std::vector<std::uint32_t> order;
  std::vector<VoxelRun> runs;
};

// Voxel indices on the grid whose voxel centres are the lattice points (i h, j h, k h): fixed,
// independent of the data, and the ground plane z = 0 runs through the middle of a voxel
// layer instead of along a voxel face (see docs/decisions/fitvox.md). Returns the packed key
// (i, j, k) lexicographic, relative to the minimum, of every point, and the number of cells.
std::vector<std::uint64_t> voxel_keys(const Scan& scan, double h, Grid* grid, std::uint64_t* cells) {
  const std::size_t n = scan.points.size();
  constexpr double kLimit = 2147483647.0;  // |index| must fit an int32
  std::vector<std::array<std::int32_t, 3>>& index = grid->index;
  index.resize(n);
  std::array<std::int64_t, 3> lo{}, hi{};
  lo.fill(std::numeric_limits<std::int64_t>::max());
  hi.fill(std::numeric_limits<std::int64_t>::min());
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      const double c = scan.points[i](d);
      const double q = std::floor(c / h + 0.5);
      if (!std::isfinite(c)) { throw Error("point " + std::to_string(i) + ": non-finite coordinate"); }
      if (!(q >= -kLimit - 1 && q <= kLimit)) {
        throw Error("voxel index overflow: point " + std::to_string(i) + " has " + "xyz"[d] +
                    fmt(" = %g m, %.3g voxels of %g m from the origin (limit 2^31); use a larger "
                        "voxel or shift the cloud",
                        c, q, h));
      }
      const auto qi = static_cast<std::int64_t>(q);
      index[i][d] = static_cast<std::int32_t>(qi);
      lo[d] = std::min(lo[d], qi);
      hi[d] = std::max(hi[d], qi);
    }
  }
  // Packed key: only an encoding, the order is the grid's. The extent must fit 2^63 keys.
  std::array<std::uint64_t, 3> ext{};
  for (int d = 0; d < 3; ++d) ext[d] = static_cast<std::uint64_t>(hi[d] - lo[d]) + 1;
  constexpr std::uint64_t kMaxKeys = std::uint64_t{1} << 63;
  if (ext[1] > kMaxKeys / ext[2] || ext[0] > kMaxKeys / (ext[1] * ext[2])) {
    throw Error(fmt("voxel index overflow: the cloud spans %.3g x %.3g x %.3g voxels",
                    static_cast<double>(ext[0]), static_cast<double>(ext[1]), static_cast<double>(ext[2])) +
                " (more than 2^63); use a larger voxel or crop the cloud");
  }
  *cells = ext[0] * ext[1] * ext[2];
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    key[i] = (static_cast<std::uint64_t>(index[i][0] - lo[0]) * ext[1] +
              static_cast<std::uint64_t>(index[i][1] - lo[1])) *
                 ext[2] +
             static_cast<std::uint64_t>(index[i][2] - lo[2]);
  }
  return key;
}

Grid voxelize(const Scan& scan, double h) {
  Grid grid;
  std::uint64_t cells = 0;
  const std::vector<std::uint64_t> key = voxel_keys(scan, h, &grid, &cells);
  const std::size_t n = key.size();
  // Order the points by (key, input index): counting sort when the grid is small, else sort.
  std::vector<std::uint32_t>& order = grid.order;
  order.resize(n);
  if (cells <= std::max<std::uint64_t>(std::uint64_t{1} << 22, 4 * static_cast<std::uint64_t>(n))) {
    std::vector<std::uint32_t> start(cells + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++start[key[i] + 1];
    for (std::uint64_t c = 0; c < cells; ++c) start[c + 1] += start[c];
    for (std::size_t i = 0; i < n; ++i) order[start[key[i]]++] = static_cast<std::uint32_t>(i);
  } else {
    for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t x, std::uint32_t y) { return key[x] != key[y] ? key[x] < key[y] : x < y; });
  }
  for (std::size_t b = 0; b < n;) {
    std::size_t e = b + 1;
    while (e < n && key[order[e]] == key[order[b]]) ++e;
    grid.runs.push_back({key[order[b]], b, e});
    b = e;
  }
  return grid;
}

// Majority label of a voxel's points (ties: the smaller label) and its share.
void majority_label(const Scan& scan, const Grid& grid, const VoxelRun& vr,
                    std::vector<std::pair<std::uint32_t, std::uint32_t>>& counts, Sample& s) {
  counts.clear();
  for (std::size_t j = vr.begin; j < vr.end; ++j) counts.push_back({scan.labels[grid.order[j]], 1});
  std::sort(counts.begin(), counts.end());
  std::uint32_t label = counts[0].first, top = 0, run_len = 0;
  for (std::size_t j = 0; j < counts.size(); ++j) {
    run_len = (j > 0 && counts[j].first == counts[j - 1].first) ? run_len + 1 : 1;
    if (run_len > top) {  // strictly more: ties keep the smaller label
      top = run_len;
      label = counts[j].first;
    }
  }
  s.label = label;
  s.label_purity = static_cast<double>(top) / static_cast<double>(vr.end - vr.begin);
}

// The fit of voxel run r about its point nearest the voxel centre (kTooFew below min_points).
// `pts` and `counts` are scratch space.
void fit_voxel(const Scan& scan, const Grid& grid, std::size_t r, const Params& params,
               std::vector<Vector3d>& pts, std::vector<std::pair<std::uint32_t, std::uint32_t>>& counts,
               Sample& s) {
  const double h = params.voxel;
  const VoxelRun& vr = grid.runs[r];
  const std::uint32_t i0 = grid.order[vr.begin];
  s.voxel = grid.index[i0];
  const Vector3d centre(grid.index[i0][0] * h, grid.index[i0][1] * h, grid.index[i0][2] * h);
  pts.clear();
  std::size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t j = vr.begin; j < vr.end; ++j) {
    const Vector3d& q = scan.points[grid.order[j]];
    const double d = (q - centre).squaredNorm();
    if (d < best_d) {  // ties: the lowest input index (order is ascending within a voxel)
      best_d = d;
      best = pts.size();
    }
    pts.push_back(q);
  }
  s.source_index = grid.order[vr.begin + best];
  s.point_count = static_cast<std::uint32_t>(pts.size());
  if (!scan.sensor.empty()) s.sensor = scan.sensor[s.source_index];
  if (!scan.labels.empty()) majority_label(scan, grid, vr, counts, s);
  if (pts.size() < static_cast<std::size_t>(params.min_points)) {
    s.fit.p = pts[best];
    s.fit.verdict = Verdict::kTooFew;
    return;
  }
  s.fit = fit_neighbourhood(pts, best, s.sensor);
}

// Noise level: the median unbiased residual sigma over every fitted voxel. Most voxels of a
// scan hold one smooth surface, so the median measures the sensor noise along the normal,
// while edges, corners and cluttered foliage voxels sit in the upper tail. 0 when none.
double median_sigma(const std::vector<Sample>& all) {
  std::vector<double> sig;
  for (const Sample& s : all) {
    if (s.fit.verdict == Verdict::kKept && s.point_count > 6) {
      sig.push_back(s.fit.rms * std::sqrt(s.point_count / (s.point_count - 6.0)));
    }
  }
  if (sig.empty()) return 0;
  auto mid = sig.begin() + static_cast<std::ptrdiff_t>((sig.size() - 1) / 2);
  std::nth_element(sig.begin(), mid, sig.end());
  return *mid;
}

// The RMS test at noise level sigma: verdicts and counts; returns the largest point count
// (at least min_points).
std::size_t apply_rms_bound(const Params& params, double sigma, std::vector<Sample>& all, Stats& stats) {
  std::size_t largest = static_cast<std::size_t>(params.min_points);
  for (Sample& s : all) {
    largest = std::max<std::size_t>(largest, s.point_count);
    switch (s.fit.verdict) {
      case Verdict::kTooFew: ++stats.too_few; break;
      case Verdict::kDegenerate: ++stats.degenerate; break;
      default:
        if (s.fit.rms > rms_bound(params, sigma, s.point_count)) {
          s.fit.verdict = Verdict::kTooRough;
          ++stats.too_rough;
        } else {
          ++stats.kept;
          if (s.fit.plane_fallback) ++stats.plane_fallback;
        }
    }
  }
  return largest;
}

// The scan points within `radius` of `centre`, searched in the voxels within `reach` of v0.
// `run_index` is the voxel index of every run (ascending).
void gather_ball(const Scan& scan, const Grid& grid, const std::vector<std::array<std::int32_t, 3>>& run_index,
                 const std::array<std::int32_t, 3>& v0, int reach, const Vector3d& centre, double radius,
                 std::vector<Vector3d>& ball) {
  auto less = [](const std::array<std::int32_t, 3>& a, const std::array<std::int32_t, 3>& b) { return a < b; };
  ball.clear();
  const double r2 = radius * radius;
  std::array<std::int32_t, 3> lo{}, hi{};
  for (int d = 0; d < 3; ++d) {
    lo[d] = static_cast<std::int32_t>(std::max<std::int64_t>(std::int64_t{v0[d]} - reach, INT32_MIN));
    hi[d] = static_cast<std::int32_t>(std::min<std::int64_t>(std::int64_t{v0[d]} + reach, INT32_MAX));
  }
  for (std::int32_t i = lo[0]; i <= hi[0]; ++i) {
    for (std::int32_t j = lo[1]; j <= hi[1]; ++j) {
      // Runs of the column (i, j, lo[2]..hi[2]) are contiguous in the sorted order.
      auto it =
          std::lower_bound(run_index.begin(), run_index.end(), std::array<std::int32_t, 3>{i, j, lo[2]}, less);
      for (; it != run_index.end() && (*it)[0] == i && (*it)[1] == j && (*it)[2] <= hi[2]; ++it) {
        const VoxelRun& vr = grid.runs[static_cast<std::size_t>(it - run_index.begin())];
        for (std::size_t q = vr.begin; q < vr.end; ++q) {
          const Vector3d& x = scan.points[grid.order[q]];
          if ((x - centre).squaredNorm() <= r2) ball.push_back(x);
        }
      }
    }
  }
}

// MLS projection of each kept voxel's start point (nearest to the centre, or the centroid)
// with a spherical support of radius stats.support that ignores voxel faces.
void project_samples(const Scan& scan, const Params& params, const Grid& grid, std::vector<Sample>& all,
                     const Stats& stats) {
  const double h = params.voxel;
  const double radius = stats.support;
  const int reach = static_cast<int>(std::ceil(radius / h + 0.5));
  // Voxel index -> run, for the neighbourhood search (runs are in (i, j, k) order).
  const std::vector<VoxelRun>& runs = grid.runs;
  std::vector<std::array<std::int32_t, 3>> run_index(runs.size());
  for (std::size_t r = 0; r < runs.size(); ++r) run_index[r] = grid.index[grid.order[runs[r].begin]];
  std::vector<Vector3d> ball;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    Sample& s = all[r];
    if (s.fit.verdict != Verdict::kKept) continue;
    Vector3d c = Vector3d::Zero();
    for (std::size_t j = runs[r].begin; j < runs[r].end; ++j) c += scan.points[grid.order[j]] - s.fit.p;
    c = s.fit.p + c / static_cast<double>(runs[r].end - runs[r].begin);
    if (!params.from_centroid) c = s.fit.p;
    gather_ball(scan, grid, run_index, run_index[r], reach, c, radius, ball);
    Fit f1 = fit_about(ball, c, s.sensor);
    if (f1.verdict != Verdict::kKept) continue;  // keep the voxel's own fit
    const Vector3d q = c + f1.a[5] * f1.w;
    gather_ball(scan, grid, run_index, run_index[r], reach, q, radius, ball);
    Fit f2 = fit_about(ball, q, s.sensor);
    if (f2.verdict != Verdict::kKept) continue;
    f2.rms = s.fit.rms;              // the voxel's own residual (the acceptance test's)
    f2.variation = s.fit.variation;  // and its points' surface variation (Samples contract)
    s.fit = f2;
  }
}

// Merge: visit kept samples by decreasing point count (ties: grid order); a sample within
// merge x voxel of an already accepted one is dropped (kMerged).
void merge_near_duplicates(const Params& params, std::vector<Sample>& all, Stats& stats) {
  std::vector<std::size_t> kept;
  for (std::size_t r = 0; r < all.size(); ++r) {
    if (all[r].fit.verdict == Verdict::kKept) kept.push_back(r);
  }
  std::stable_sort(kept.begin(), kept.end(),
                   [&](std::size_t a, std::size_t b) { return all[a].point_count > all[b].point_count; });
  const double md = params.merge * params.voxel;
  const double cell = std::max(md, 1e-12);
  auto cell_of = [&](const Vector3d& x) {
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(x(0) / cell)),
                                       static_cast<std::int64_t>(std::floor(x(1) / cell)),
                                       static_cast<std::int64_t>(std::floor(x(2) / cell))};
  };
  std::map<std::array<std::int64_t, 3>, std::vector<std::size_t>> accepted;
  auto near_accepted = [&](const Vector3d& x, const std::array<std::int64_t, 3>& c0) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = accepted.find({c0[0] + dx, c0[1] + dy, c0[2] + dz});
          if (it == accepted.end()) continue;
          for (std::size_t o : it->second) {
            if ((all[o].fit.p - x).norm() < md) return true;
          }
        }
      }
    }
    return false;
  };
  for (std::size_t r : kept) {
    const Vector3d& x = all[r].fit.p;
    const auto c0 = cell_of(x);
    if (near_accepted(x, c0)) {
      all[r].fit.verdict = Verdict::kMerged;
      ++stats.merged;
      --stats.kept;
    } else {
      accepted[c0].push_back(r);
    }
  }
}

}  // namespace

Outputs run(const Params& params, const Inputs& scan) {
  check_input(scan, params);
  Result result;
  result.stats.points = scan.points.size();
  if (scan.points.empty()) return result;
  const double h = params.voxel;
  const Grid grid = voxelize(scan, h);
  result.stats.voxels = grid.runs.size();

  // Per-voxel fits (independent, so any thread count gives the same result).
  std::vector<Sample> all(grid.runs.size());
  common::parallel_for(grid.runs.size(), params.threads, [&](std::size_t first, std::size_t last) {
    std::vector<Vector3d> pts;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> counts;
    for (std::size_t r = first; r < last; ++r) fit_voxel(scan, grid, r, params, pts, counts, all[r]);
  });

  result.stats.sigma_estimated = median_sigma(all);
  const double sigma = params.noise < 0 ? result.stats.sigma_estimated : params.noise;
  result.stats.sigma = sigma;
  const std::size_t largest = apply_rms_bound(params, sigma, all, result.stats);
  if (params.resample) {
    result.stats.support = params.support > 0 ? params.support * h : std::clamp(6 * sigma, h / 2, h);
    project_samples(scan, params, grid, all, result.stats);
    if (params.merge > 0) merge_near_duplicates(params, all, result.stats);
  }
  result.stats.rms_bound_at_max_points = rms_bound(params, sigma, largest);
  result.stats.rms_bound_at_min_points = rms_bound(params, sigma, static_cast<std::size_t>(params.min_points));
  result.stats.max_points = largest;
  std::tie(result.stats.rms_bound_least, result.stats.rms_bound_greatest) =
      rms_bound_range(params, sigma, static_cast<std::size_t>(params.min_points), largest);
  result.samples.reserve(result.stats.kept);
  for (const Sample& s : all) {
    if (s.fit.verdict == Verdict::kKept) result.samples.push_back(s);
  }
  if (params.keep_all) result.all = std::move(all);
  return result;
}

Scan scan_from_cloud(const formats::PointCloud& cloud, const std::string& name, bool* has_sensor) {
  cloud.require({"x", "y", "z"}, name, "is this a point cloud?");
  Scan scan;
  scan.points = formats::finite_vectors(cloud, name);
  const int sensor_fields =
      int(cloud.has("sensor_x")) + int(cloud.has("sensor_y")) + int(cloud.has("sensor_z"));
  if (sensor_fields != 0 && sensor_fields != 3) {
    throw common::DataError(name, "needs all of sensor_x, sensor_y, sensor_z or none of them");
  }
  if (has_sensor != nullptr) *has_sensor = sensor_fields == 3;
  if (sensor_fields == 3) {
    scan.sensor = formats::to_vectors(cloud, formats::kSensorFields);
    for (std::size_t i = 0; i < scan.sensor.size(); ++i) {
      if (!scan.sensor[i].allFinite() || scan.sensor[i].squaredNorm() == 0) {
        throw common::DataError(name,
                                "point " + std::to_string(i) + ": sensor direction is zero or not finite");
      }
    }
  }
  if (cloud.has("label")) scan.labels = formats::uint32_column(cloud, "label", name);
  return scan;
}

formats::PointCloud samples_to_cloud(const Result& result) {
  using formats::kFloat32;
  using formats::kUint32;
  formats::PointCloud c;
  const char* const f4[] = {"x",
                            "y",
                            "z",
                            "normal_x",
                            "normal_y",
                            "normal_z",
                            "curvature",
                            "mean_curvature",
                            "gauss_curvature",
                            "u_x",
                            "u_y",
                            "u_z",
                            "v_x",
                            "v_y",
                            "v_z",
                            "w_x",
                            "w_y",
                            "w_z",
                            "a0",
                            "a1",
                            "a2",
                            "a3",
                            "a4",
                            "a5",
                            "rms"};
  for (const char* name : f4) c.add(name, kFloat32);
  c.add("point_count", kUint32);
  c.add("label", kUint32);
  c.add("label_purity", kFloat32);
  for (const char* name : {"sensor_x", "sensor_y", "sensor_z"}) c.add(name, kFloat32);
  const std::size_t n = result.samples.size();
  c.resize(n);
  std::vector<std::vector<double>*> col;
  for (const std::string& name : c.names()) col.push_back(&c.col(name));
  for (std::size_t i = 0; i < n; ++i) {
    const Sample& s = result.samples[i];
    const Fit& f = s.fit;
    std::size_t j = 0;
    auto put = [&](double value) { (*col[j++])[i] = value; };
    auto put3 = [&](const Vector3d& q) {
      put(q(0));
      put(q(1));
      put(q(2));
    };
    put3(f.p);
    put3(f.normal);
    put(f.variation);
    put(f.mean_curvature);
    put(f.gauss_curvature);
    put3(f.u);
    put3(f.v);
    put3(f.w);
    for (double a : f.a) put(a);
    put(f.rms);
    put(s.point_count);
    put(s.label);
    put(s.label_purity);
    put3(s.sensor);
  }
  return c;
}

}  // namespace canopy::fitvox
