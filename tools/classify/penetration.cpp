// classify's penetration cues (docs/decisions/classify.md §5, §14, §20): below_share and
// ground_through, point by point, and with Params::sight_lines only the points whose line of sight
// passes through the object; the echo widening (§25); late returns (§5, §22, §26).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "canopy/common/math.h"
#include "canopy/common/stats.h"
#include "classify/features.h"

namespace canopy::classify {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kInf = std::numeric_limits<double>::infinity();

// Per crop point: whether it is a later return split off by the object's edge
// (Params::ground_through_edges, classify.md §23): every earlier return of its pulse (same
// point_source_id, gps_time, number_of_returns; returns 1 .. k - 1 all present) is an object point
// on the edge of the object's solid layer. The layer: the object points that ended their pulse
// (its last return; points of unknown pulses too). On its edge: the layer's points within `ring`
// = max(0.5 m, 2.5 spacings: some 20 points of a flat top) horizontally and 0.25 m vertically of
// it are fewer than 3 or leave an angular gap of at least three eighths of a turn (on a straight
// edge about half a turn; amid a layer of 20 points the largest gap passes that for under 1% of the
// points). `q` are the object's points (`object`: their indices in c) in any horizontal frame.
std::vector<bool> edge_splits(const Candidate& c, const std::vector<std::size_t>& object,
                              const std::vector<Vector3d>& q, const Params& fp, double spacing) {
  std::vector<bool> split(c.points.size(), false);
  if (!fp.ground_through_edges || c.time.empty() || c.return_number.empty() || object.empty()) return split;
  const Pulses pulses(c);
  auto last = [&](std::size_t i) {
    if (!pulses.known(i)) return true;
    for (std::size_t j : pulses.of(i)) {
      if (c.return_number[j] > c.return_number[i]) return false;
    }
    return true;
  };
  const double ring = std::max(0.5, 2.5 * spacing);
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> grid;
  for (std::size_t k = 0; k < q.size(); ++k) {
    if (last(object[k])) grid[cell_key(cell_of(q[k].x(), ring), cell_of(q[k].y(), ring))].push_back(k);
  }
  auto on_edge = [&](std::size_t k) {
    std::vector<double> angles;
    const std::int64_t ca = cell_of(q[k].x(), ring), cb = cell_of(q[k].y(), ring);
    for (std::int64_t da = -1; da <= 1; ++da) {
      for (std::int64_t db = -1; db <= 1; ++db) {
        const auto it = grid.find(cell_key(ca + da, cb + db));
        if (it == grid.end()) continue;
        for (std::size_t j : it->second) {
          const double dx = q[j].x() - q[k].x(), dy = q[j].y() - q[k].y();
          const double h = std::hypot(dx, dy);
          if (h > 1e-9 && h <= ring && std::abs(q[j].z() - q[k].z()) <= 0.25)
            angles.push_back(std::atan2(dy, dx));
        }
      }
    }
    if (angles.size() < 3) return true;
    std::sort(angles.begin(), angles.end());
    double gap = angles.front() + 2 * common::kPi - angles.back();
    for (std::size_t m = 1; m < angles.size(); ++m) gap = std::max(gap, angles[m] - angles[m - 1]);
    return gap >= 0.75 * common::kPi;
  };
  std::vector<int> slot(c.points.size(), -1);  // index into `object` / `q`
  for (std::size_t k = 0; k < object.size(); ++k) slot[object[k]] = static_cast<int>(k);
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    const int k = c.return_number[i];
    if (k <= 1 || !pulses.known(i)) continue;
    std::vector<bool> found(static_cast<std::size_t>(k), false);
    bool edge = true;
    for (std::size_t j : pulses.of(i)) {
      const int r = c.return_number[j];
      if (r < 1 || r >= k) continue;
      if (slot[j] < 0 || !on_edge(static_cast<std::size_t>(slot[j]))) edge = false;
      found[static_cast<std::size_t>(r)] = true;
    }
    split[i] = edge && std::all_of(found.begin() + 1, found.end(), [](bool b) { return b; });
  }
  return split;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return common::sorted_quantile(v, 0.5);
}

// Per crop point: whether a later return counts for late_returns (Params::late_returns_inside,
// classify.md §22). Every point counts without the option, without gps_time or for a point
// whose time is unknown; with them a later return counts only when each earlier return of its
// pulse (same point_source_id, gps_time, number_of_returns) is in the crop at or below the
// object's top.
std::vector<bool> split_inside(const Candidate& c, const std::vector<std::size_t>& object, const Params& fp) {
  std::vector<bool> inside(c.points.size(), true);
  if (!(fp.late_returns_inside || fp.late_shadow) || c.time.empty() || c.return_number.empty() ||
      object.empty())
    return inside;
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i : object) top = std::max(top, c.points[i].z());
  const Pulses pulses(c);
  for (std::size_t i : object) {
    const int k = c.return_number[i];
    if (k <= 1 || !pulses.known(i)) continue;
    // Earlier returns 1 .. k - 1 found at or below the top.
    std::vector<bool> found(static_cast<std::size_t>(k), false);
    for (std::size_t j : pulses.of(i)) {
      const int r = c.return_number[j];
      if (r >= 1 && r < k && c.points[j].z() <= top) found[static_cast<std::size_t>(r)] = true;
    }
    inside[i] = std::all_of(found.begin() + 1, found.end(), [](bool b) { return b; });
  }
  return inside;
}

}  // namespace

// The echo widening (classify.md §25): the median echo width of the object's returns over the
// median of the crop's open-ground returns that were the only return of their pulse (the pulse's
// own width on a level hard surface: the reference needs no sensor constant). At least
// kEchoReference of those and 3 object returns with a known width, else unknown.
namespace {
constexpr std::size_t kEchoReference = 10;
}  // namespace

void echo_cue(const Candidate& c, const std::vector<std::size_t>& object, const Params& fp, Features& f) {
  if (c.echo_width.empty()) return;
  std::vector<double> ground, own;
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    const double w = c.echo_width[i];
    if (!std::isfinite(w) || w <= 0 || c.points[i].z() >= fp.ground_cut) continue;
    if (!c.number_of_returns.empty() && c.number_of_returns[i] != 1) continue;
    ground.push_back(w);
  }
  for (std::size_t i : object) {
    const double w = c.echo_width[i];
    if (std::isfinite(w) && w > 0) own.push_back(w);
  }
  if (ground.size() < kEchoReference || own.size() < 3) return;
  f.echo_widening = median(own) / median(ground);
}

void penetration_cues(const Candidate& c, const std::vector<std::size_t>& object,
                      const std::vector<char>& counted, bool all, const std::vector<Vector3d>& q, double u0,
                      double vm, const Vector2d& u, const Vector2d& v, Features& f, const Params& fp) {
  const double inset = std::max(0.4, f.spacing);
  const double rb = std::max(0.2, f.spacing), rg = std::max(0.1, 0.5 * f.spacing);
  const double L = f.length_measured, W = f.width_measured;
  auto interior = [&](double a, double b) {
    return a >= inset && a <= L - inset && std::abs(b) <= W / 2 - inset;
  };
  const double cell = rb;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> grid;
  for (std::size_t i = 0; i < q.size(); ++i)
    grid[cell_key(cell_of(q[i].x(), cell), cell_of(q[i].y(), cell))].push_back(i);
  // The highest object point within `radius` of (a, b), or -inf.
  auto highest = [&](double a, double b, double radius) {
    double best = -kInf;
    const std::int64_t ca = cell_of(a, cell), cb = cell_of(b, cell);
    for (std::int64_t da = -1; da <= 1; ++da) {
      for (std::int64_t db = -1; db <= 1; ++db) {
        const auto it = grid.find(cell_key(ca + da, cb + db));
        if (it == grid.end()) continue;
        for (std::size_t j : it->second) {
          const double dx = q[j].x() - a, dy = q[j].y() - b;
          if (dx * dx + dy * dy <= radius * radius) best = std::max(best, q[j].z());
        }
      }
    }
    return best;
  };
  // Whether the line of sight of point i (at `at`, in the rectangle's frame) passes through the
  // object: from 0.3 m above the point to the object's top, in 0.05 m steps, an object point
  // within `tube` (horizontally and vertically) of the line, or object points around the line
  // (within `ring` horizontally and 0.25 m vertically, no angular gap of half a turn or more: the
  // line crosses a layer of the object, not beside its edge). Unknown direction: through.
  const double tube = 0.5 * f.spacing, ring = 1.5 * f.spacing;
  const double top =
      q.empty() ? 0 : std::max_element(q.begin(), q.end(), [](const Vector3d& x, const Vector3d& y) {
                        return x.z() < y.z();
                      })->z();
  const std::int64_t reach = static_cast<std::int64_t>(std::ceil(std::max(tube, ring) / cell));
  auto through = [&](std::size_t i, const Vector3d& at) {
    if (!fp.sight_lines || c.view.empty()) return true;
    const Vector3d& w = c.view[i];
    if (w.z() <= 1e-3) return true;
    const Vector3d d(w.x() * u.x() + w.y() * u.y(), w.x() * v.x() + w.y() * v.y(), w.z());
    std::vector<double> angles;
    for (double t = 0.05;; t += 0.05) {
      const Vector3d s = at + t * d;
      if (s.z() > top + 0.05) return false;
      if (s.z() < at.z() + 0.3) continue;
      angles.clear();
      const std::int64_t ca = cell_of(s.x(), cell), cb = cell_of(s.y(), cell);
      for (std::int64_t da = -reach; da <= reach; ++da) {
        for (std::int64_t db = -reach; db <= reach; ++db) {
          const auto it = grid.find(cell_key(ca + da, cb + db));
          if (it == grid.end()) continue;
          for (std::size_t j : it->second) {
            const double dx = q[j].x() - s.x(), dy = q[j].y() - s.y(), dz = q[j].z() - s.z();
            const double h = std::hypot(dx, dy);
            if (h <= tube && std::abs(dz) <= tube) return true;
            if (h <= ring && h > 1e-9 && std::abs(dz) <= 0.25) angles.push_back(std::atan2(dy, dx));
          }
        }
      }
      if (angles.size() < 3) continue;
      std::sort(angles.begin(), angles.end());
      double gap = angles.front() + 2 * common::kPi - angles.back();
      for (std::size_t k = 1; k < angles.size(); ++k) gap = std::max(gap, angles[k] - angles[k - 1]);
      if (gap < common::kPi) return true;
    }
  };
  std::size_t inner = 0, below = 0, under = 0, below_any = 0, under_any = 0;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const Vector3d& p = q[k];
    if (!interior(p.x(), p.y())) continue;
    ++inner;
    if (highest(p.x(), p.y(), rb) >= p.z() + 0.5) {
      ++below_any;
      below += through(object[k], p);
    }
  }
  const std::vector<bool> split = edge_splits(c, object, q, fp, f.spacing);
  std::size_t under_all = 0, edges = 0;
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    const Vector3d& p = c.points[i];
    if (p.z() >= fp.ground_cut || !(counted[i] || all)) continue;
    const Vector2d xy(p.x(), p.y());
    const double a = xy.dot(u) - u0, b = xy.dot(v) - vm;
    if (interior(a, b) && highest(a, b, rg) >= p.z() + 0.5) {
      if (split[i]) {
        edges += counted[i];
        continue;
      }
      under_any += counted[i];
      if (!through(i, Vector3d(a, b, p.z()))) continue;
      under_all += 1;
      under += counted[i];
    }
  }
  auto share = [&](std::size_t n) {
    return inner + n ? static_cast<double>(n) / static_cast<double>(inner + n) : 0.0;
  };
  f.interior_points = inner;
  f.below_share = inner ? static_cast<double>(below) / static_cast<double>(inner) : 0;
  f.ground_through = share(under);
  if (all) f.ground_through_all_passes = share(under_all);
  if (fp.ground_through_edges && !c.time.empty() && !c.return_number.empty()) f.ground_edge_splits = edges;
  if (fp.sight_lines) {
    f.below_share_any = inner ? static_cast<double>(below_any) / static_cast<double>(inner) : 0;
    f.ground_through_any = share(under_any);
  }
}

// classify.md §5, §22, §26: late_returns, multi_returns, and the shade around the object.
void late_cues(const Candidate& c, const std::vector<std::size_t>& object, const std::vector<char>& counted,
               const Vector2d& u, const Vector2d& v, double u0, double u1, double v0, double v1,
               const Params& fp, Features& f) {
  if (c.return_number.empty()) return;
  // The shade around the object (classify.md §26): the same ground returns' later-return share;
  // read by late_shadow and written beside late_shadowed, so measured only with one of the options.
  if (fp.late_returns_inside || fp.late_shadow) {
    std::size_t known = 0, later = 0;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      const Vector3d& p = c.points[i];
      if (p.z() >= fp.ground_cut || !counted[i] || c.return_number[i] == 0 || c.number_of_returns[i] == 0)
        continue;
      const Vector2d xy(p.x(), p.y());
      const double a = xy.dot(u), b = xy.dot(v);
      if (a >= u0 && a <= u1 && b >= v0 && b <= v1) continue;
      ++known;
      later += c.return_number[i] > 1;
    }
    f.ring_returns = known;
    if (known >= 10) f.ring_shadowed = static_cast<double>(later) / static_cast<double>(known);
  }
  std::size_t late = 0, shadowed = 0, multi = 0, known = 0;
  const std::vector<bool> inside = split_inside(c, object, fp);
  for (std::size_t i : object) {
    if (c.return_number[i] == 0 || c.number_of_returns[i] == 0) continue;
    ++known;
    late += c.return_number[i] > 1 && inside[i];
    shadowed += c.return_number[i] > 1 && !inside[i];
    multi += c.number_of_returns[i] > 1;
  }
  if (known == 0) return;
  // Shadowed returns: none with late_returns_inside (§22), weighed by the shade around the
  // object with late_shadow (§26; full weight when the shade is unknown).
  const double weight = fp.late_shadow ? f.ring_shadowed.value_or(1.0) : 0.0;
  const double n = static_cast<double>(known);
  f.late_returns = (static_cast<double>(late) + weight * static_cast<double>(shadowed)) / n;
  f.multi_returns = static_cast<double>(multi) / n;
  if ((fp.late_returns_inside || fp.late_shadow) && !c.time.empty())
    f.late_shadowed = static_cast<double>(shadowed) / n;
}

}  // namespace canopy::classify
