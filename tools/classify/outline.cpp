// classify's outline cues (docs/decisions/classify.md §16): the top's height profile along the
// long axis, its concavities (notch, dents), and the shape of its narrowest end (tip_width,
// tip_level); across the width, the shoulder (§30), the rim (§38) and a pickup's bed (§39).
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <vector>

#include "classify/features.h"

#include "canopy/common/stats.h"

namespace canopy::classify {

namespace {

// Each profile bin's depth under the profile's upper convex hull (monotone chain), share of H. A
// convex outline (a box, an ellipsoid, a rounded caravan roof) lies on the hull; a bonnet or boot
// below the cabin lies under it.
std::vector<double> depth_under_hull(const std::vector<double>& x, const std::vector<double>& z, double H) {
  std::vector<std::size_t> hull;
  for (std::size_t i = 0; i < x.size(); ++i) {
    while (hull.size() >= 2) {
      const std::size_t a = hull[hull.size() - 2], b = hull.back();
      const double cross = (x[b] - x[a]) * (z[i] - z[a]) - (z[b] - z[a]) * (x[i] - x[a]);
      if (cross < 0) break;  // b stays above the chord a-i
      hull.pop_back();
    }
    hull.push_back(i);
  }
  std::vector<double> depth(x.size(), 0);
  for (std::size_t k = 0; k + 1 < hull.size(); ++k) {
    const std::size_t a = hull[k], b = hull[k + 1];
    for (std::size_t i = a + 1; i < b; ++i) {
      const double t = (x[i] - x[a]) / (x[b] - x[a]);
      depth[i] = (z[a] + t * (z[b] - z[a]) - z[i]) / H;
    }
  }
  return depth;
}

}  // namespace

void outline_cues(const std::vector<Eigen::Vector3d>& q, Features& f) {
  const double H = std::max(f.height_measured, 1e-6);
  const double L = f.length_measured, W = std::max(f.width_measured, 1e-6);
  // The profile: the highest point of each bin along the long axis (bins of the plateau's
  // size, max(0.25 m, spacing): about one sample per bin and row across the width).
  const double bin = std::max(0.25, f.spacing);
  const auto bins = static_cast<std::size_t>(std::max(1.0, std::ceil(L / bin)));
  std::vector<double> top(bins, -std::numeric_limits<double>::infinity());
  std::vector<std::size_t> count(bins, 0);
  for (const Eigen::Vector3d& p : q) {
    const auto b = std::min(bins - 1, static_cast<std::size_t>(std::max(0.0, p.x() / bin)));
    top[b] = std::max(top[b], p.z());
    ++count[b];
  }
  std::vector<double> x, z;    // the filled bins: centre, top
  std::vector<std::size_t> n;  // and their points
  for (std::size_t b = 0; b < bins; ++b) {
    if (std::isfinite(top[b])) {
      x.push_back((static_cast<double>(b) + 0.5) * bin);
      z.push_back(top[b]);
      n.push_back(count[b]);
    }
  }
  const std::vector<double> depth = depth_under_hull(x, z, H);
  // The notch: the deepest bin. (Sustained over two neighbouring bins, as first written, it lost
  // 4 of the 29 clear development cars answered as cars: at 8 points/m² a real bonnet is one or
  // two bins below the chord, its windscreen unsampled; classify.md §16.)
  f.notch = 0;
  f.dents = 0;
  bool in_dent = false;
  for (const double d : depth) {
    f.notch = std::max(f.notch, d);
    const bool deep = d >= kDentDepth;
    f.dents += deep && !in_dent;
    in_dent = deep;
  }
  // The sampled notch (§37): the same, over the profile of the bins holding at least
  // kSampledShare of the filled bins' median count. Rows of samples cross every bin at least once
  // (bins >= the spacing), so a bin under half the median holds less than one row across the
  // width: its highest sample need not be its top (the rows beat against the bins, or a crown hid
  // part of it), and a rock's or tent's smooth top shows a "step" there. A bonnet or boot is a
  // bin sampled like its neighbours, only lower.
  {
    std::vector<double> m(n.begin(), n.end());
    std::sort(m.begin(), m.end());
    const double median = m.empty() ? 0 : common::sorted_quantile(m, 0.5);
    std::vector<double> xs, zs;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (static_cast<double>(n[i]) >= kSampledShare * median) {
        xs.push_back(x[i]);
        zs.push_back(z[i]);
      }
    }
    f.notch_sampled = 0;
    for (const double d : depth_under_hull(xs, zs, H)) f.notch_sampled = std::max(f.notch_sampled, d);
  }
  // The tips: the outermost max(0.4 m, 1.5 x spacing) of each end (at most a quarter of the
  // length). Width = the points' extent across (+ one spacing: the samples lie inside the
  // edges, and a single point is that wide) over W; level = their highest over H. The tip
  // reported is the narrower end's (a trailer's drawbar: narrow and low; a vehicle's bumper,
  // bonnet or tail fills most of its width at half its height or more).
  const double slice = std::min(std::max(0.4, 1.5 * f.spacing), 0.25 * L);
  auto tip = [&](bool front) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, up = 0;
    for (const Eigen::Vector3d& p : q) {
      if (front ? p.x() > slice : p.x() < L - slice) continue;
      lo = std::min(lo, p.y());
      hi = std::max(hi, p.y());
      up = std::max(up, p.z());
    }
    if (hi < lo) return std::pair<double, double>(0, 0);
    return std::pair<double, double>(std::min(1.0, (hi - lo + f.spacing) / W), up / H);
  };
  const auto a = tip(true), b = tip(false);
  const auto& narrow = a.first < b.first || (a.first == b.first && a.second <= b.second) ? a : b;
  f.tip_width = narrow.first;
  f.tip_level = narrow.second;
  // The shoulder (§30): the body's height at its sides, in the middle of its length.
  // The rim (§38): each side of that band against the centre band (a roof's middle, a deck's floor).
  std::vector<double> side, left, right, centre;
  for (const Eigen::Vector3d& p : q) {
    if (p.x() < 0.2 * L || p.x() > 0.8 * L) continue;
    if (std::abs(p.y()) > kShoulderBand * W / 2) {
      side.push_back(p.z());
      (p.y() > 0 ? left : right).push_back(p.z());
    }
    if (std::abs(p.y()) < kRimCentre * W / 2) centre.push_back(p.z());
  }
  f.shoulder.reset();
  f.rim.reset();
  if (side.size() >= kShoulderPoints) {
    std::sort(side.begin(), side.end());
    f.shoulder = common::sorted_quantile(side, 0.9) / H;
  }
  if (left.size() >= kShoulderPoints && right.size() >= kShoulderPoints && centre.size() >= kShoulderPoints) {
    for (auto* v : {&left, &right, &centre}) std::sort(v->begin(), v->end());
    const double lower = std::min(common::sorted_quantile(left, 0.9), common::sorted_quantile(right, 0.9));
    f.rim = (lower - common::sorted_quantile(centre, 0.9)) / H;
  }
  // The bed (§39): at each end, over [kBedFrom L, kBedTo L] from it, the same bands. A side point
  // stands over the centre by its height less the higher of the two centre points on either side
  // of it along the length (a bonnet's or windscreen's slope under a side point lies between them:
  // it never stands over them; a bed's floor does not slope); walls = the lower side's 0.9 quantile
  // of that (a bed's walls over its floor), under = H less the higher side's 0.9 quantile of its
  // heights (the walls under the cab's roof); bed = the smaller of the two over H, at the end where
  // it is larger.
  f.bed.reset();
  for (const bool far : {false, true}) {
    std::vector<Eigen::Vector2d> c;  // the centre band's (along, height), sorted
    std::vector<Eigen::Vector2d> sides[2];
    for (const Eigen::Vector3d& p : q) {
      const double from_end = far ? L - p.x() : p.x();
      if (from_end < kBedFrom * L || from_end > kBedTo * L) continue;
      if (std::abs(p.y()) > kShoulderBand * W / 2) sides[p.y() > 0].emplace_back(p.x(), p.z());
      if (std::abs(p.y()) < kRimCentre * W / 2) c.emplace_back(p.x(), p.z());
    }
    if (c.size() < kShoulderPoints) continue;
    std::sort(c.begin(), c.end(),
              [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() < b.x(); });
    double walls = std::numeric_limits<double>::infinity(), top = -walls;
    bool measured = true;
    for (const std::vector<Eigen::Vector2d>& side : sides) {
      std::vector<double> over, z;
      for (const Eigen::Vector2d& p : side) {
        z.push_back(p.y());
        const auto hi = std::lower_bound(c.begin(), c.end(), p.x(),
                                         [](const Eigen::Vector2d& a, double x) { return a.x() < x; });
        if (hi == c.end() || hi == c.begin()) continue;  // no centre point beyond it on one side
        over.push_back(p.y() - std::max(hi->y(), std::prev(hi)->y()));
      }
      if (over.size() < kShoulderPoints) {
        measured = false;
        break;
      }
      std::sort(over.begin(), over.end());
      std::sort(z.begin(), z.end());
      walls = std::min(walls, common::sorted_quantile(over, 0.9));
      top = std::max(top, common::sorted_quantile(z, 0.9));
    }
    if (!measured) continue;
    const double bed = std::min(walls, H - top) / H;
    if (!f.bed || bed > *f.bed) f.bed = bed;
  }
}

}  // namespace canopy::classify
