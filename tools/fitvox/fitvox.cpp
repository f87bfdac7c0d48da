#include "fitvox/fitvox.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <thread>
#include <utility>

#include "canopy/common/error.h"

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
            std::isfinite(f.rms) && std::isfinite(f.variation) &&
            std::isfinite(f.mean_curvature) && std::isfinite(f.gauss_curvature);
  for (double c : f.a) ok = ok && std::isfinite(c);
  return ok;
}

std::string fmt(const char* format, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

}  // namespace

Fit fit_neighbourhood(const std::vector<Vector3d>& points, std::size_t p_index,
                      const Vector3d& toward) {
  if (p_index >= points.size()) return Fit{};
  return fit_about(points, points[p_index], toward);
}

Fit fit_about(const std::vector<Vector3d>& points, const Vector3d& p, const Vector3d& toward) {
  Fit f;
  f.verdict = Verdict::kDegenerate;
  const std::size_t k = points.size();
  f.p = p;
  if (k < 3) return f;

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
  if (es.info() != Eigen::Success) return f;
  const Vector3d ev = es.eigenvalues();  // ascending
  if (!(ev(2) > 0) || !(ev(1) > kCollinear * ev(2))) return f;  // coincident or collinear
  f.u = es.eigenvectors().col(2).normalized();
  f.v = es.eigenvectors().col(1).normalized();
  f.w = f.u.cross(f.v).normalized();
  const double lambda_min = std::max(ev(0), 0.0);
  f.variation = lambda_min / (lambda_min + ev(1) + ev(2));

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
  if (k >= 6) {
    Eigen::Matrix<double, Eigen::Dynamic, 6> m(k, 6);
    for (std::size_t i = 0; i < k; ++i) {
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
    for (std::size_t i = 0; i < k; ++i) m.row(i) << t(i, 0), t(i, 1), 1.0;
    Eigen::ColPivHouseholderQR<Eigen::Matrix<double, Eigen::Dynamic, 3>> qr(m);
    qr.setThreshold(kRankThreshold);
    if (qr.rank() < 3) return f;
    const Eigen::Vector3d x = qr.solve(t.col(2));
    a = {0, 0, 0, x(0), x(1), x(2)};
  }
  // Unscale: w/s = a (u/s)² + ... => quadratic terms / s, linear unchanged, constant * s.
  a[0] /= s;
  a[1] /= s;
  a[2] /= s;
  a[5] *= s;

  double sse = 0;
  for (std::size_t i = 0; i < k; ++i) {
    const double u = uvw(i, 0), v = uvw(i, 1);
    const double r = uvw(i, 2) - (a[0] * u * u + a[1] * u * v + a[2] * v * v + a[3] * u +
                                  a[4] * v + a[5]);
    sse += r * r;
  }
  f.rms = std::sqrt(sse / static_cast<double>(k));

  // Orient: the biquadratic's normal at p is (-f_u, -f_v, 1) in (u, v, w). If it faces away
  // from the sensor, turn the frame half a turn about u (v -> -v, w -> -w, still
  // right-handed); in the new frame w' = -f(u, -v'), which negates a0, a2, a3, a5.
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
  f.mean_curvature = ((1 + a[4] * a[4]) * 2 * a[0] - 2 * a[3] * a[4] * a[1] +
                      (1 + a[3] * a[3]) * 2 * a[2]) /
                     (2 * std::pow(g, 1.5));
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

namespace {

struct VoxelRun {
  std::uint64_t key;
  std::size_t begin, end;  // range in the sorted order
};

void validate(const Scan& scan, const Params& params) {
  if (!(params.voxel > 0) || !std::isfinite(params.voxel)) {
    throw Error("voxel edge must be a positive length");
  }
  if (params.min_points < 6) throw Error("min-points must be at least 6 (a biquadratic has 6 coefficients)");
  if (!(params.max_rms >= 0) || !std::isfinite(params.max_rms)) throw Error("max-rms must be >= 0");
  if (!std::isfinite(params.noise)) throw Error("noise must be finite");
  if (!(params.noise_margin >= 0) || !std::isfinite(params.noise_margin)) {
    throw Error("noise-margin must be >= 0");
  }
  if (params.threads < 1) throw Error("threads must be >= 1");
  if (!(params.support > 0 || params.support < 0) || !std::isfinite(params.support)) {
    throw Error("support must be > 0 (voxel edges) or < 0 (auto)");
  }
  if (!(params.merge >= 0) || !std::isfinite(params.merge)) throw Error("merge must be >= 0");
  const std::size_t n = scan.points.size();
  if (!scan.sensor.empty() && scan.sensor.size() != n) {
    throw Error("sensor directions: " + std::to_string(scan.sensor.size()) + " for " +
                std::to_string(n) + " points");
  }
  if (!scan.labels.empty() && scan.labels.size() != n) {
    throw Error("labels: " + std::to_string(scan.labels.size()) + " for " + std::to_string(n) +
                " points");
  }
  if (n > std::numeric_limits<std::uint32_t>::max()) throw Error("more than 2^32 points");
}

}  // namespace

namespace {

// Resampling of the kept voxels (Params::resample): MLS projection of each voxel's start point
// (nearest to the centre, or the centroid) with a spherical support that ignores voxel faces,
// then merging of near-duplicates.
void resample(const Scan& scan, const Params& params,
              const std::vector<std::array<std::int32_t, 3>>& index,
              const std::vector<std::uint32_t>& order, const std::vector<VoxelRun>& runs,
              std::vector<Sample>& all, Stats& stats) {
  const double h = params.voxel;
  const double radius = stats.support;
  const int reach = static_cast<int>(std::ceil(radius / h + 0.5));
  // Voxel index -> run, for the neighbourhood search (runs are in (i, j, k) order).
  auto less = [](const std::array<std::int32_t, 3>& a, const std::array<std::int32_t, 3>& b) { return a < b; };
  std::vector<std::array<std::int32_t, 3>> run_index(runs.size());
  for (std::size_t r = 0; r < runs.size(); ++r) run_index[r] = index[order[runs[r].begin]];
  std::vector<Vector3d> ball;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    Sample& s = all[r];
    if (s.fit.verdict != Verdict::kKept) continue;
    Vector3d c = Vector3d::Zero();
    for (std::size_t j = runs[r].begin; j < runs[r].end; ++j) c += scan.points[order[j]] - s.fit.p;
    c = s.fit.p + c / static_cast<double>(runs[r].end - runs[r].begin);
    if (!params.from_centroid) c = s.fit.p;
    const std::array<std::int32_t, 3> v0 = run_index[r];
    auto gather = [&](const Vector3d& centre) {
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
          auto it = std::lower_bound(run_index.begin(), run_index.end(), std::array<std::int32_t, 3>{i, j, lo[2]}, less);
          for (; it != run_index.end() && (*it)[0] == i && (*it)[1] == j && (*it)[2] <= hi[2]; ++it) {
            const VoxelRun& vr = runs[static_cast<std::size_t>(it - run_index.begin())];
            for (std::size_t q = vr.begin; q < vr.end; ++q) {
              const Vector3d& x = scan.points[order[q]];
              if ((x - centre).squaredNorm() <= r2) ball.push_back(x);
            }
          }
        }
      }
    };
    gather(c);
    Fit f1 = fit_about(ball, c, s.sensor);
    if (f1.verdict != Verdict::kKept) continue;  // keep the voxel's own fit
    const Vector3d q = c + f1.a[5] * f1.w;
    gather(q);
    Fit f2 = fit_about(ball, q, s.sensor);
    if (f2.verdict != Verdict::kKept) continue;
    f2.rms = s.fit.rms;              // the voxel's own residual (the acceptance test's)
    f2.variation = s.fit.variation;  // and its points' surface variation (Samples contract)
    s.fit = f2;
  }
  if (!(params.merge > 0)) return;
  // Merge: visit kept samples by decreasing point count (ties: grid order); a sample within
  // merge x voxel of an already accepted one is dropped.
  std::vector<std::size_t> kept;
  for (std::size_t r = 0; r < all.size(); ++r) {
    if (all[r].fit.verdict == Verdict::kKept) kept.push_back(r);
  }
  std::stable_sort(kept.begin(), kept.end(),
                   [&](std::size_t a, std::size_t b) { return all[a].point_count > all[b].point_count; });
  const double md = params.merge * h;
  const double cell = std::max(md, 1e-12);
  auto cell_of = [&](const Vector3d& x) {
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(x(0) / cell)),
                                       static_cast<std::int64_t>(std::floor(x(1) / cell)),
                                       static_cast<std::int64_t>(std::floor(x(2) / cell))};
  };
  std::map<std::array<std::int64_t, 3>, std::vector<std::size_t>> accepted;
  for (std::size_t r : kept) {
    const Vector3d& x = all[r].fit.p;
    const auto c0 = cell_of(x);
    bool near = false;
    for (int dx = -1; dx <= 1 && !near; ++dx) {
      for (int dy = -1; dy <= 1 && !near; ++dy) {
        for (int dz = -1; dz <= 1 && !near; ++dz) {
          const auto it = accepted.find({c0[0] + dx, c0[1] + dy, c0[2] + dz});
          if (it == accepted.end()) continue;
          for (std::size_t o : it->second) {
            if ((all[o].fit.p - x).norm() < md) {
              near = true;
              break;
            }
          }
        }
      }
    }
    if (near) {
      all[r].fit.verdict = Verdict::kMerged;
      ++stats.merged;
      --stats.kept;
    } else {
      accepted[c0].push_back(r);
    }
  }
}

}  // namespace

Result run(const Scan& scan, const Params& params, bool keep_all) {
  validate(scan, params);
  Result result;
  const std::size_t n = scan.points.size();
  result.stats.points = n;
  if (n == 0) return result;

  // Voxel indices on the grid whose voxel centres are the lattice points (i h, j h, k h): fixed,
  // independent of the data, and the ground plane z = 0 runs through the middle of a voxel
  // layer instead of along a voxel face (see docs/decisions/fitvox.md).
  const double h = params.voxel;
  constexpr double kLimit = 2147483647.0;  // |index| must fit an int32
  std::vector<std::array<std::int32_t, 3>> index(n);
  std::array<std::int64_t, 3> lo{}, hi{};
  lo.fill(std::numeric_limits<std::int64_t>::max());
  hi.fill(std::numeric_limits<std::int64_t>::min());
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      const double c = scan.points[i](d);
      const double q = std::floor(c / h + 0.5);
      if (!std::isfinite(c)) {
        throw Error("point " + std::to_string(i) + ": non-finite coordinate");
      }
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
  // Packed key (i, j, k) lexicographic, relative to the minimum: only an encoding, the order is
  // the grid's. The extent must fit 2^63 keys.
  std::array<std::uint64_t, 3> ext{};
  for (int d = 0; d < 3; ++d) ext[d] = static_cast<std::uint64_t>(hi[d] - lo[d]) + 1;
  constexpr std::uint64_t kMaxKeys = std::uint64_t{1} << 63;
  if (ext[1] > kMaxKeys / ext[2] || ext[0] > kMaxKeys / (ext[1] * ext[2])) {
    throw Error(fmt("voxel index overflow: the cloud spans %.3g x %.3g x %.3g voxels",
                    static_cast<double>(ext[0]), static_cast<double>(ext[1]),
                    static_cast<double>(ext[2])) +
                " (more than 2^63); use a larger voxel or crop the cloud");
  }
  const std::uint64_t cells = ext[0] * ext[1] * ext[2];
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    key[i] = (static_cast<std::uint64_t>(index[i][0] - lo[0]) * ext[1] +
              static_cast<std::uint64_t>(index[i][1] - lo[1])) *
                 ext[2] +
             static_cast<std::uint64_t>(index[i][2] - lo[2]);
  }

  // Order the points by (key, input index): counting sort when the grid is small, else sort.
  std::vector<std::uint32_t> order(n);
  if (cells <= std::max<std::uint64_t>(std::uint64_t{1} << 22, 4 * static_cast<std::uint64_t>(n))) {
    std::vector<std::uint32_t> start(cells + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++start[key[i] + 1];
    for (std::uint64_t c = 0; c < cells; ++c) start[c + 1] += start[c];
    for (std::size_t i = 0; i < n; ++i) order[start[key[i]]++] = static_cast<std::uint32_t>(i);
  } else {
    for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
      return key[x] != key[y] ? key[x] < key[y] : x < y;
    });
  }
  std::vector<VoxelRun> runs;
  for (std::size_t b = 0; b < n;) {
    std::size_t e = b + 1;
    while (e < n && key[order[e]] == key[order[b]]) ++e;
    runs.push_back({key[order[b]], b, e});
    b = e;
  }
  result.stats.voxels = runs.size();

  // Per-voxel fits (independent, so any thread count gives the same result).
  std::vector<Sample> all(runs.size());
  auto work = [&](std::size_t first, std::size_t last) {
    std::vector<Vector3d> pts;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> counts;
    for (std::size_t r = first; r < last; ++r) {
      const VoxelRun& vr = runs[r];
      Sample& s = all[r];
      const std::uint32_t i0 = order[vr.begin];
      s.voxel = index[i0];
      const Vector3d centre(index[i0][0] * h, index[i0][1] * h, index[i0][2] * h);
      pts.clear();
      std::size_t best = 0;
      double best_d = std::numeric_limits<double>::infinity();
      for (std::size_t j = vr.begin; j < vr.end; ++j) {
        const Vector3d& q = scan.points[order[j]];
        const double d = (q - centre).squaredNorm();
        if (d < best_d) {  // ties: the lowest input index (order is ascending within a voxel)
          best_d = d;
          best = pts.size();
        }
        pts.push_back(q);
      }
      s.source_index = order[vr.begin + best];
      s.point_count = static_cast<std::uint32_t>(pts.size());
      if (!scan.sensor.empty()) s.sensor = scan.sensor[s.source_index];
      if (!scan.labels.empty()) {
        counts.clear();
        for (std::size_t j = vr.begin; j < vr.end; ++j) counts.push_back({scan.labels[order[j]], 1});
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
        s.label_purity = static_cast<double>(top) / static_cast<double>(pts.size());
      }
      if (pts.size() < static_cast<std::size_t>(params.min_points)) {
        s.fit.p = pts[best];
        s.fit.verdict = Verdict::kTooFew;
        continue;
      }
      s.fit = fit_neighbourhood(pts, best, s.sensor);
    }
  };
  const std::size_t threads =
      std::min<std::size_t>(static_cast<std::size_t>(params.threads), runs.size());
  if (threads <= 1) {
    work(0, runs.size());
  } else {
    std::vector<std::thread> pool;
    const std::size_t chunk = (runs.size() + threads - 1) / threads;
    for (std::size_t t = 0; t < threads; ++t) {
      const std::size_t first = t * chunk, last = std::min(runs.size(), first + chunk);
      if (first < last) pool.emplace_back(work, first, last);
    }
    for (std::thread& th : pool) th.join();
  }

  // Noise level: the median unbiased residual sigma over every fitted voxel. Most voxels of a
  // scan hold one smooth surface, so the median measures the sensor noise along the normal,
  // while edges, corners and cluttered foliage voxels sit in the upper tail.
  std::vector<double> sig;
  for (const Sample& s : all) {
    if (s.fit.verdict == Verdict::kKept && s.point_count > 6) {
      sig.push_back(s.fit.rms * std::sqrt(s.point_count / (s.point_count - 6.0)));
    }
  }
  if (!sig.empty()) {
    auto mid = sig.begin() + static_cast<std::ptrdiff_t>((sig.size() - 1) / 2);
    std::nth_element(sig.begin(), mid, sig.end());
    result.stats.sigma_estimated = *mid;
  }
  const double sigma = params.noise < 0 ? result.stats.sigma_estimated : params.noise;
  result.stats.sigma = sigma;

  std::size_t largest = static_cast<std::size_t>(params.min_points);
  for (Sample& s : all) {
    largest = std::max<std::size_t>(largest, s.point_count);
    switch (s.fit.verdict) {
      case Verdict::kTooFew: ++result.stats.too_few; break;
      case Verdict::kDegenerate: ++result.stats.degenerate; break;
      default:
        if (s.fit.rms > rms_bound(params, sigma, s.point_count)) {
          s.fit.verdict = Verdict::kTooRough;
          ++result.stats.too_rough;
        } else {
          ++result.stats.kept;
          if (s.fit.plane_fallback) ++result.stats.plane_fallback;
        }
    }
  }
  if (params.resample) {
    result.stats.support = params.support > 0 ? params.support * h : std::clamp(6 * sigma, h / 2, h);
    resample(scan, params, index, order, runs, all, result.stats);
  }
  result.stats.rms_bound_at_max_points = rms_bound(params, sigma, largest);
  result.stats.rms_bound_at_min_points = rms_bound(params, sigma, static_cast<std::size_t>(params.min_points));
  result.samples.reserve(result.stats.kept);
  for (const Sample& s : all) {
    if (s.fit.verdict == Verdict::kKept) result.samples.push_back(s);
  }
  if (keep_all) result.all = std::move(all);
  return result;
}

Scan scan_from_cloud(const formats::PointCloud& cloud, const std::string& name,
                     bool* has_sensor) {
  cloud.require({"x", "y", "z"}, name, "is this a point cloud?");
  Scan scan;
  const std::size_t n = cloud.size();
  const auto& x = cloud.col("x");
  const auto& y = cloud.col("y");
  const auto& z = cloud.col("z");
  scan.points.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    scan.points[i] = Vector3d(x[i], y[i], z[i]);
    if (!scan.points[i].allFinite()) {
      throw common::DataError(name, "point " + std::to_string(i) + " has a non-finite coordinate");
    }
  }
  const int sensor_fields = int(cloud.has("sensor_x")) + int(cloud.has("sensor_y")) +
                            int(cloud.has("sensor_z"));
  if (sensor_fields != 0 && sensor_fields != 3) {
    throw common::DataError(name, "needs all of sensor_x, sensor_y, sensor_z or none of them");
  }
  if (has_sensor != nullptr) *has_sensor = sensor_fields == 3;
  if (sensor_fields == 3) {
    const auto& sx = cloud.col("sensor_x");
    const auto& sy = cloud.col("sensor_y");
    const auto& sz = cloud.col("sensor_z");
    scan.sensor.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      scan.sensor[i] = Vector3d(sx[i], sy[i], sz[i]);
      if (!scan.sensor[i].allFinite() || scan.sensor[i].squaredNorm() == 0) {
        throw common::DataError(name, "point " + std::to_string(i) +
                                          ": sensor direction is zero or not finite");
      }
    }
  }
  if (cloud.has("label")) {
    const auto& l = cloud.col("label");
    scan.labels.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (!(l[i] >= 0 && l[i] <= 4294967295.0) || l[i] != std::floor(l[i])) {
        throw common::DataError(name, "point " + std::to_string(i) + ": label is not a uint32");
      }
      scan.labels[i] = static_cast<std::uint32_t>(l[i]);
    }
  }
  return scan;
}

formats::PointCloud samples_to_cloud(const Result& result) {
  using formats::kFloat32;
  using formats::kUint32;
  formats::PointCloud c;
  const char* const f4[] = {"x", "y", "z", "normal_x", "normal_y", "normal_z", "curvature",
                            "mean_curvature", "gauss_curvature", "u_x", "u_y", "u_z", "v_x",
                            "v_y", "v_z", "w_x", "w_y", "w_z", "a0", "a1", "a2", "a3", "a4",
                            "a5", "rms"};
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
