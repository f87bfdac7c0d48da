#include "synth_scan.h"

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "canopy/common/math.h"
#include "canopy/common/rng.h"

namespace fitvox_bench {
namespace {

using Eigen::Vector3d;

struct Box {
  Vector3d lo, hi;
};

struct Disc {
  Vector3d c, n;
  double r;
};

// Tank-like: two tracks, hull, turret, barrel (m). Top at z = 2.2.
const std::array<Box, 5> kVehicle = {{
    {{-3.5, -1.8, 0.0}, {3.5, -1.3, 1.0}},
    {{-3.5, 1.3, 0.0}, {3.5, 1.8, 1.0}},
    {{-3.2, -1.3, 0.4}, {3.2, 1.3, 1.5}},
    {{-1.2, -1.1, 1.5}, {1.4, 1.1, 2.2}},
    {{1.4, -0.08, 1.75}, {4.6, 0.08, 1.91}},
}};
constexpr double kTop = 2.2;
constexpr double kInf = std::numeric_limits<double>::infinity();

double hit_box(const Box& b, const Vector3d& o, const Vector3d& d) {
  double t0 = -kInf, t1 = kInf;
  for (int k = 0; k < 3; ++k) {
    if (d(k) == 0) {
      if (o(k) < b.lo(k) || o(k) > b.hi(k)) return kInf;
      continue;
    }
    double a = (b.lo(k) - o(k)) / d(k), c = (b.hi(k) - o(k)) / d(k);
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
  }
  return (t0 <= t1 && t0 > 0) ? t0 : kInf;
}

double hit_disc(const Disc& s, const Vector3d& o, const Vector3d& d) {
  const double dn = d.dot(s.n);
  if (std::abs(dn) < 1e-12) return kInf;
  const double t = (s.c - o).dot(s.n) / dn;
  if (t <= 0) return kInf;
  return ((o + t * d) - s.c).squaredNorm() <= s.r * s.r ? t : kInf;
}

std::vector<Disc> random_discs(const SceneOptions& opt) {
  canopy::common::Rng geo(canopy::common::derive_seed(opt.seed, "foliage"));
  std::vector<Disc> discs;
  for (int i = 0; i < opt.discs; ++i) {
    Disc s;
    s.c = Vector3d(geo.uniform(-6.1, 6.1), geo.uniform(-6.1, 6.1), geo.uniform(kTop, kTop + 2));
    s.n = Vector3d(geo.normal(), geo.normal(), geo.normal()).normalized();
    s.r = 0.1;
    discs.push_back(s);
  }
  return discs;
}

const Vector3d kCentre(0, 0, 1.1);  // vehicle centre; crop box 10 x 4 x 4 m around it
constexpr int kCell = 8;            // pixels per bucket side

// One orthographic view: towards the sensor s, image axes right and up, ray direction d.
struct View {
  Vector3d s, right, up, d;
};

// The discs whose projection covers each kCell x kCell image cell (nc x nc cells).
std::vector<std::vector<int>> bucket_discs(const std::vector<Disc>& discs, const View& v,
                                           const SceneOptions& opt, double half, int nc) {
  std::vector<std::vector<int>> bucket(static_cast<std::size_t>(nc * nc));
  for (int i = 0; i < static_cast<int>(discs.size()); ++i) {
    const Vector3d rel = discs[i].c - kCentre;
    const double a = rel.dot(v.right) / opt.spacing + half, b = rel.dot(v.up) / opt.spacing + half;
    const double rad = discs[i].r / opt.spacing + 1;
    const int i0 = std::max(0, static_cast<int>(std::floor((a - rad) / kCell)));
    const int i1 = std::min(nc - 1, static_cast<int>(std::floor((a + rad) / kCell)));
    const int j0 = std::max(0, static_cast<int>(std::floor((b - rad) / kCell)));
    const int j1 = std::min(nc - 1, static_cast<int>(std::floor((b + rad) / kCell)));
    for (int ci = i0; ci <= i1; ++ci) {
      for (int cj = j0; cj <= j1; ++cj) bucket[static_cast<std::size_t>(ci * nc + cj)].push_back(i);
    }
  }
  return bucket;
}

// Nearest hit of the ray o + t d among ground, vehicle and the given discs: its t and label
// (0 = no hit).
std::uint32_t trace(const Vector3d& o, const Vector3d& d, const std::vector<Disc>& discs,
                    const std::vector<int>& candidates, double& best) {
  best = kInf;
  std::uint32_t label = 0;
  const double tg = -o.z() / d.z();  // ground z = 0
  if (tg > 0) {
    best = tg;
    label = 3;
  }
  for (const Box& b : kVehicle) {
    const double t = hit_box(b, o, d);
    if (t < best) {
      best = t;
      label = 1;
    }
  }
  for (int i : candidates) {
    const double t = hit_disc(discs[static_cast<std::size_t>(i)], o, d);
    if (t < best) {
      best = t;
      label = 2;
    }
  }
  return label;
}

}  // namespace

canopy::fitvox::Scan synth_scan(const SceneOptions& opt) {
  const std::vector<Disc> discs = random_discs(opt);
  const Vector3d& centre = kCentre;
  const Vector3d crop_lo = centre - Vector3d(5, 2, 2), crop_hi = centre + Vector3d(5, 2, 2);

  canopy::fitvox::Scan scan;
  const double el = opt.elevation_deg * canopy::common::kPi / 180;
  const int np = opt.pixels;
  const double half = 0.5 * (np - 1);
  const int nc = (np + kCell - 1) / kCell;
  for (int view = 0; view < opt.views; ++view) {
    const double az = 2 * canopy::common::kPi * view / opt.views;
    View v;
    v.s = Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    v.right = Vector3d(-std::sin(az), std::cos(az), 0);
    v.up = v.s.cross(v.right);
    v.d = -v.s;
    const std::vector<std::vector<int>> bucket = bucket_discs(discs, v, opt, half, nc);
    for (int pi = 0; pi < np; ++pi) {
      for (int pj = 0; pj < np; ++pj) {
        const Vector3d o =
            centre + 100 * v.s + (pi - half) * opt.spacing * v.right + (pj - half) * opt.spacing * v.up;
        double best;
        const std::uint32_t label =
            trace(o, v.d, discs, bucket[static_cast<std::size_t>((pi / kCell) * nc + pj / kCell)], best);
        if (label == 0) continue;
        const Vector3d q = o + best * v.d;
        if ((q.array() < crop_lo.array()).any() || (q.array() > crop_hi.array()).any()) continue;
        scan.points.push_back(q);
        scan.sensor.push_back(v.s);
        scan.labels.push_back(label);
      }
    }
  }
  if (opt.sigma > 0) {
    canopy::common::Rng noise(canopy::common::derive_seed(opt.seed, "noise"));
    for (Vector3d& q : scan.points) {
      q += opt.sigma * Vector3d(noise.normal(), noise.normal(), noise.normal());
    }
  }
  return scan;
}

}  // namespace fitvox_bench
