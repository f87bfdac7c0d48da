#include "detect/fragments.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

#include <Eigen/Core>

#include "detect/footprint.h"
#include "detect/plan.h"

namespace canopy::detect {
namespace {

using Eigen::Vector2d;

struct Tile {
  const std::vector<double>& x;
  const std::vector<double>& y;
  const std::vector<float>& h;  // height above the DTM
};

}  // namespace

// Fragments under a crown (detect.md §24): the part of a vehicle that a crown hides returns few
// points, sparse and scattered by the gaps in the foliage, and the clustering leaves them apart
// from the rest of it in clusters too small to be objects (an end of a sedan, the cab of a
// semi-tractor or of an earthmover in 1-30 points at 25-50 points/m²). A fragment is merged into
// an accepted object when at least half of its points have a tile point over them (in their voxel
// column or the eight around it) higher than the union's top by a voxel (a crown, not the
// vehicle's own higher part), it comes within merge_gap voxels of the object in the top view (or,
// with merge_fragments_gap, at most that far when the gap between them is hidden: a crown over
// all of it and no ground seen in it), the union stays in line (no wider than the object +
// kMergeWiden) and fits the vehicle ranges, and (with merge_fragments_beside) it lies beside the
// object, not over it. Repeated until none merges (a fragment that reaches the object only through another
// one merges after it); the first object found takes it.
std::size_t merge_fragments(const std::vector<double>& x, const std::vector<double>& y,
                            const std::vector<float>& height, const Params& p,
                            const std::vector<Fragment>& fragments, std::vector<Object>& objs) {
  const double reach = std::max(p.merge_gap, 0.0) * p.voxel, v = p.voxel;
  if (!p.merge_fragments || reach <= 0 || fragments.empty()) return 0;
  const Tile c{x, y, height};
  // The highest tile point of each voxel column (above the DTM, whatever its height) and, for the
  // hidden gap, the points under min_object_height (the ground) by voxel column.
  std::unordered_map<std::uint64_t, float> column_top;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> ground;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const std::uint64_t key = column_key(x[i], y[i], v);
    float& top = column_top.emplace(key, height[i]).first->second;
    top = std::max(top, height[i]);
    if (p.merge_fragments_gap > 0 && height[i] < p.min_object_height) ground[key].push_back(std::uint32_t(i));
  }
  std::size_t count = 0;
  // True when the tile's highest point in the voxel columns around (x, y) is above `top` + a voxel.
  auto crown_over = [&](double x, double y, double top) {
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        const auto it = column_top.find(column_key(x + di * v, y + dj * v, v));
        if (it != column_top.end() && double(it->second) > top + v) return true;
      }
    return false;
  };
  // True when at least half of `pts` have a crown over them.
  auto covered = [&](const std::vector<std::uint32_t>& pts, double top) {
    std::size_t under = 0;
    for (std::uint32_t q : pts) under += crown_over(c.x[q], c.y[q], top);
    return under * 2 >= pts.size();
  };
  // The closest pair in the top view (a fragment's point, the object's point) and their distance.
  auto closest = [&](const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    std::pair<std::uint32_t, std::uint32_t> best{0, 0};
    double d = 1e300;
    for (std::uint32_t q : a)
      for (std::uint32_t r : b) {
        const double e = std::hypot(c.x[q] - c.x[r], c.y[q] - c.y[r]);
        if (e < d) {
          d = e;
          best = {q, r};
        }
      }
    return std::make_pair(best, d);
  };
  // A gap no one saw into: every step of a voxel/4 along the segment from q to r has a crown
  // over it, and no tile point under min_object_height (the ground) lies within half a voxel of it
  // between its ends. Between two parts of one vehicle the body hides the ground; between a vehicle
  // and a separate body the sensor sees it where no crown hides it.
  auto hidden_gap = [&](std::uint32_t q, std::uint32_t r, double top) {
    const Vector2d a(c.x[q], c.y[q]), b(c.x[r], c.y[r]);
    const double len = (b - a).norm();
    const int steps = std::max(1, int(std::ceil(len / (0.25 * v))));
    for (int k = 0; k <= steps; ++k) {
      const Vector2d m = a + (b - a) * (double(k) / steps);
      if (!crown_over(m.x(), m.y(), top)) return false;
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj) {
          const auto it = ground.find(column_key(m.x() + di * v, m.y() + dj * v, v));
          if (it == ground.end()) continue;
          for (std::uint32_t g : it->second) {
            const Vector2d gp(c.x[g], c.y[g]);
            const double t = (gp - a).dot(b - a) / std::max(1e-12, len * len);
            if (t > 0 && t < 1 && (gp - m).norm() < 0.5 * v) return false;
          }
        }
    }
    return true;
  };
  std::vector<char> used(fragments.size(), 0);
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t f = 0; f < fragments.size(); ++f) {
      if (used[f]) continue;
      const auto& frag = fragments[f].points;
      const Footprint ff = plan_footprint(c.x, c.y, frag);
      double ftop = 0;
      for (std::uint32_t q : frag) ftop = std::max(ftop, double(c.h[q]));
      for (auto& o : objs) {
        const double far = p.merge_fragments_gap > 0 ? std::max(reach, p.merge_fragments_gap) : reach;
        if ((o.fp.centre - ff.centre).norm() >
            0.5 * (std::hypot(o.fp.length, o.fp.width) + std::hypot(ff.length, ff.width)) + far)
          continue;
        const double top = std::max(o.height, ftop);
        if (!touch_in_plan(c.x, c.y, frag, o.points, reach)) {
          if (far <= reach) continue;
          const auto [pair, d] = closest(frag, o.points);
          if (d > far || !hidden_gap(pair.first, pair.second, top)) continue;
        }
        std::vector<std::uint32_t> both = o.points;
        both.insert(both.end(), frag.begin(), frag.end());
        const Footprint u = plan_footprint(c.x, c.y, both);
        if (u.length > p.max_length || u.width > p.max_width || u.width > o.fp.width + kMergeWiden) continue;
        if (!covered(frag, top)) continue;
        // Beside the object, not over it (join_stacked's test): a crown's low bottom over a
        // container or a caravan shares their top-view cells; a hidden end or cab does not.
        if (p.merge_fragments_beside && over_in_plan(c.x, c.y, frag, o.points, reach)) continue;
        std::sort(both.begin(), both.end());
        o.points = std::move(both);
        o.fp = u;
        o.height = std::max(o.height, ftop);
        if (fragments[f].examination >= 0) o.lineage.push_back(fragments[f].examination);
        used[f] = 1;
        ++count;
        merged = true;
        break;
      }
    }
  }
  return count;
}

}  // namespace canopy::detect
