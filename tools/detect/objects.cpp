#include "detect/objects.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>

#include "canopy/common/error.h"
#include "canopy/formats/csv_table.h"
#include "detect/clustering.h"
#include "detect/fragments.h"
#include "detect/plan.h"
#include "detect/rows.h"

namespace canopy::detect {
namespace {

using common::DataError;
using Eigen::Vector2d;
using formats::format_number;

constexpr int kMaxSplitDepth = 6;

struct Context {
  const Params& p;
  const std::vector<double>& x;  // local frame
  const std::vector<double>& y;
  const std::vector<double>& z;  // height above the DTM (clustering in (x, y, height))
  const std::vector<float>& h;
  Objects& out;  // accepted objects and counts
  // 2-D voxel columns (i, j at `voxel`, packed) holding a point just above the band: a
  // cluster reaching the band's top under them is the bottom of something taller (a crown).
  std::unordered_map<std::uint64_t, char> above;
  // With end_gap: the tile's points under min_object_height (ground, grass) by voxel column.
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> ground;
  int in_row = 0;                     // > 0 while examining the pieces of a row split (rows.h)
  int in_trim = 0;                    // > 0 while examining the pieces of a trim (rows.h)
  std::size_t origin = 0;             // the cluster being examined (find_objects' order)
  std::vector<std::int32_t> lineage;  // the examinations under way, outermost first
  std::int32_t examinations = 0;      // examinations numbered so far
  // With merge_fragments: the clusters of the clustering rejected as too small (fragments.h).
  std::vector<Fragment> fragments;
};

// True when most of the cluster's points in the band's top voxel layer have points right
// above the band over them (within one voxel column): a crown or building cut by the band.
bool continues_upward(const Context& c, const std::vector<std::uint32_t>& pts) {
  const double v = c.p.voxel, top = c.p.max_height - v;
  std::size_t in_top = 0, under = 0;
  for (std::uint32_t q : pts) {
    if (c.h[q] < top) continue;
    ++in_top;
    bool hit = false;
    for (int di = -1; di <= 1 && !hit; ++di)
      for (int dj = -1; dj <= 1 && !hit; ++dj)
        hit = c.above.count(column_key(c.x[q] + di * v, c.y[q] + dj * v, v)) > 0;
    under += hit;
  }
  return in_top >= 10 && under * 2 >= in_top;
}

// Finer voxel (half the edge): parts of `pts` that only touch come apart. Returns the parts
// holding at least max(min_points, min_share of the points) when there are two or more and
// together they hold at least `min_kept` of the points: objects that touch come apart whole,
// while a sparsely sampled one only falls into fragments (returns 0.2-0.4 m apart at half a
// 0.2-0.4 m voxel), of which the larger would be taken for objects and the rest lost
// (detect.md §10).
std::vector<std::vector<std::uint32_t>> finer_parts(const Context& c, const std::vector<std::uint32_t>& pts,
                                                    double min_share = 0.1, double min_kept = 0.0) {
  std::vector<std::vector<std::uint32_t>> parts;
  try {
    parts = cluster_points(pts, c.x, c.y, c.z, c.p.voxel / 2, Clustering::kGrid);
  } catch (const VoxelOverflow&) {
    return {};  // too large for the finer voxel: no finer parts
  }
  const std::size_t big = std::max(c.p.min_points, std::size_t(double(pts.size()) * min_share));
  std::vector<std::vector<std::uint32_t>> kept;
  std::size_t held = 0;
  for (auto& part : parts) {
    if (part.size() >= big) {
      held += part.size();
      kept.push_back(std::move(part));
    }
  }
  if (kept.size() < 2 || double(held) < min_kept * double(pts.size())) kept.clear();
  return kept;
}

// Extent of `pts` along `axis`.
std::pair<double, double> span_along(const Context& c, const std::vector<std::uint32_t>& pts,
                                     const Vector2d& axis) {
  double lo = 1e300, hi = -1e300;
  for (std::uint32_t q : pts) {
    const double s = Vector2d(c.x[q], c.y[q]).dot(axis);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  return {lo, hi};
}

// True when two extents along one axis overlap by more than half the shorter one.
bool overlap_half(const std::pair<double, double>& a, const std::pair<double, double>& b) {
  const double overlap = std::min(a.second, b.second) - std::max(a.first, b.first);
  return overlap > 0.5 * std::min(a.second - a.first, b.second - b.first);
}

// True when the parts lie side by side across `cross` (the object's short axis): no two of them
// overlap along it by more than half the narrower one's extent. Two vehicles parked side by side
// do; the front and rear halves of one wide, sparsely sampled vehicle (8 x 3.1 m, 25 points/m²)
// that a half voxel parts do not (detect.md §10).
bool side_by_side(const Context& c, const std::vector<std::vector<std::uint32_t>>& parts,
                  const Vector2d& cross) {
  std::vector<std::pair<double, double>> span;
  for (const auto& part : parts) span.push_back(span_along(c, part, cross));
  for (std::size_t a = 0; a < span.size(); ++a)
    for (std::size_t b = a + 1; b < span.size(); ++b)
      if (overlap_half(span[a], span[b])) return false;
  return true;
}

// The object's points along `axis` in slabs: their extent [smin, smax], the slabs' width (0.05 m,
// widened up to 0.2 m until a slab holds 20 points on average), each slab's points and its
// highest point's height above the ground. valley_cut's and end_gap_cut's profile.
struct SlabProfile {
  double smin = 1e300, smax = -1e300, bin = 0.05;
  std::vector<double> count, top;
};
SlabProfile slab_profile(const Context& c, const std::vector<std::uint32_t>& pts, const Vector2d& axis) {
  SlabProfile prof;
  std::vector<double> s(pts.size());
  for (std::size_t n = 0; n < pts.size(); ++n) {
    s[n] = Vector2d(c.x[pts[n]], c.y[pts[n]]).dot(axis);
    prof.smin = std::min(prof.smin, s[n]);
    prof.smax = std::max(prof.smax, s[n]);
  }
  while (prof.bin < 0.2 && double(pts.size()) * prof.bin / std::max(1e-9, prof.smax - prof.smin) < 20)
    prof.bin *= 2;
  const int nb = std::max(1, int(std::ceil((prof.smax - prof.smin) / prof.bin)));
  prof.count.assign(std::size_t(nb), 0.0);
  prof.top.assign(std::size_t(nb), 0.0);
  for (std::size_t n = 0; n < pts.size(); ++n) {
    const int b = std::min(nb - 1, int((s[n] - prof.smin) / prof.bin));
    prof.count[std::size_t(b)] += 1;
    prof.top[std::size_t(b)] = std::max(prof.top[std::size_t(b)], double(c.h[pts[n]]));
  }
  return prof;
}

// Cut position across `axis` at a clear valley, leaving at least `min_side` on each side; NaN
// if none. A valley is an empty gap (a slab holding at most 35% of the median slab's points)
// or a drop of the top surface between two higher parts (the highest
// point of the bin at least max(0.3 m, 20% of the lower part) below the highest on either
// side): two car roofs side by side. The deepest valley wins, then the one nearest the middle.
double valley_cut(const Context& c, const std::vector<std::uint32_t>& pts, const Vector2d& axis,
                  double min_side, double min_gap) {
  const SlabProfile prof = slab_profile(c, pts, axis);
  const double smin = prof.smin, smax = prof.smax, bin = prof.bin;
  const std::vector<double>& slab = prof.count;
  const std::vector<double>& top = prof.top;
  const int nb = int(slab.size());
  std::vector<double> sorted = slab;
  std::nth_element(sorted.begin(), sorted.begin() + long(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2];
  std::vector<double> left(std::size_t(nb), 0.0), right(std::size_t(nb), 0.0);
  for (int b = 1; b < nb; ++b)
    left[std::size_t(b)] = std::max(left[std::size_t(b - 1)], top[std::size_t(b - 1)]);
  for (int b = nb - 2; b >= 0; --b)
    right[std::size_t(b)] = std::max(right[std::size_t(b + 1)], top[std::size_t(b + 1)]);
  // An empty slab is a gap between two bodies only when the run of empty slabs it lies in is at
  // least min_gap wide: narrower runs are the spaces between the scan lines over one body's top
  // when the lines run along the axis of the cut (detect.md §14).
  std::vector<double> run(std::size_t(nb), 0.0);
  for (int b = 0; b < nb;) {
    int e = b;
    while (e < nb && slab[std::size_t(e)] <= 0.35 * median) ++e;
    for (int k = b; k < e; ++k) run[std::size_t(k)] = (e - b) * bin;
    b = e > b ? e : b + 1;
  }
  double best_depth = 0, best_off = 1e300, cut = std::numeric_limits<double>::quiet_NaN();
  const double mid = 0.5 * (smin + smax);
  for (int b = 0; b < nb; ++b) {
    const double centre = smin + (b + 0.5) * bin;
    if (centre - smin < min_side || smax - centre < min_side) continue;
    const double lower = std::min(left[std::size_t(b)], right[std::size_t(b)]);
    const double drop = lower - top[std::size_t(b)];
    const bool empty = slab[std::size_t(b)] <= 0.35 * median;
    // A narrow empty run is neither a gap nor a dip (its top is not measured, not low).
    if (empty && run[std::size_t(b)] < min_gap - 1e-9) continue;
    const bool dip = drop >= std::max(0.3, 0.2 * lower);
    if (!empty && !dip) continue;
    const double depth = empty ? lower : drop;
    const double off = std::abs(centre - mid);
    if (depth > best_depth + 1e-9 || (std::abs(depth - best_depth) <= 1e-9 && off < best_off)) {
      best_depth = depth;
      best_off = off;
      cut = centre;
    }
  }
  return cut;
}

// Cut position along `axis` (the object's long axis) at a gap between two bodies end to end;
// NaN if none. A gap is a run of slabs (slab_profile, as valley_cut's) holding none of the object's
// points, at least `min_run` long, over which a point of the tile under min_object_height lies
// in the middle half of the object's extent across the axis: the sensor saw the ground between
// the two (beside one body it sees the ground all along it, under its middle never). A run
// over one body's top (scan lines, a windscreen that returned nothing) hides the ground under it;
// a slab holding a few points is a narrow part of one body (a wheel loader's articulation, a
// drawbar), not a gap. The longest run wins, then the one nearest the middle.
double end_gap_cut(const Context& c, const std::vector<std::uint32_t>& pts, const Vector2d& axis,
                   double min_run) {
  const Vector2d across(-axis.y(), axis.x());
  const SlabProfile prof = slab_profile(c, pts, axis);
  const double smin = prof.smin, smax = prof.smax, bin = prof.bin;
  const std::vector<double>& slab = prof.count;
  const int nb = int(slab.size());
  double tmin = 1e300, tmax = -1e300;
  for (std::uint32_t q : pts) {
    const double t = Vector2d(c.x[q], c.y[q]).dot(across);
    tmin = std::min(tmin, t);
    tmax = std::max(tmax, t);
  }
  // True when a ground point lies over [s0, s1] in the middle half of the object's width: beside
  // one body the ground is seen along all of it, under the middle of its width only between two.
  const double t0 = 0.75 * tmin + 0.25 * tmax, t1 = 0.25 * tmin + 0.75 * tmax;
  auto ground_in = [&](double s0, double s1) {
    const double v = c.p.voxel;
    Eigen::AlignedBox2d box;
    for (double a : {s0, s1})
      for (double b : {t0, t1}) box.extend(axis * a + across * b);
    for (double gx = std::floor(box.min().x() / v) * v; gx <= box.max().x() + 1e-9; gx += v)
      for (double gy = std::floor(box.min().y() / v) * v; gy <= box.max().y() + 1e-9; gy += v) {
        const auto it = c.ground.find(column_key(gx + 0.5 * v, gy + 0.5 * v, v));
        if (it == c.ground.end()) continue;
        for (std::uint32_t q : it->second) {
          const Vector2d g(c.x[q], c.y[q]);
          const double gs = g.dot(axis), gt = g.dot(across);
          if (gs >= s0 && gs <= s1 && gt >= t0 && gt <= t1) return true;
        }
      }
    return false;
  };
  double best_run = 0, best_off = 1e300, cut = std::numeric_limits<double>::quiet_NaN();
  const double mid = 0.5 * (smin + smax);
  for (int b = 0; b < nb;) {
    int e = b;
    while (e < nb && slab[std::size_t(e)] <= 0.0) ++e;
    if (e == b) {
      ++b;
      continue;
    }
    const double s0 = smin + b * bin, s1 = smin + e * bin, run = s1 - s0;
    // Inside the object only: a run at either end is no gap between two bodies.
    if (b > 0 && e < nb && run >= min_run - 1e-9 && ground_in(s0, s1)) {
      const double centre = 0.5 * (s0 + s1), off = std::abs(centre - mid);
      if (run > best_run + 1e-9 || (std::abs(run - best_run) <= 1e-9 && off < best_off)) {
        best_run = run;
        best_off = off;
        cut = centre;
      }
    }
    b = e;
  }
  return cut;
}

void examine(Context& c, std::vector<std::uint32_t> pts, int depth) {
  const Params& p = c.p;
  // With object_field: this examination's number on its points and on the lineage while it lasts
  // (Objects::examined).
  const bool numbered = p.object_field;
  if (numbered) {
    const std::int32_t id = c.examinations++;
    for (std::uint32_t q : pts) c.out.examined[q] = id;
    c.lineage.push_back(id);
  }
  struct Pop {
    std::vector<std::int32_t>& s;
    bool on;
    ~Pop() {
      if (on) s.pop_back();
    }
  } pop{c.lineage, numbered};
  // A cluster of the clustering too small alone: kept aside for merge_fragments.
  auto fragment = [&] {
    if (p.merge_fragments && depth == 0 && !pts.empty())
      c.fragments.push_back({pts, numbered ? c.lineage.back() : -1});
  };
  if (pts.size() < p.min_points) {
    ++c.out.rejected_small;
    fragment();
    return;
  }
  Object o;
  o.fp = plan_footprint(c.x, c.y, pts);
  for (std::uint32_t q : pts) o.height = std::max(o.height, double(c.h[q]));
  if (o.fp.length < p.min_length || o.fp.width < p.min_width || o.height < p.min_height) {
    ++c.out.rejected_small;
    fragment();
    return;
  }
  if (continues_upward(c, pts)) {
    // A vehicle close under a crown may hang on to its bottom: a finer voxel parts them.
    auto parts = depth < kMaxSplitDepth ? finer_parts(c, pts, 0.0) : std::vector<std::vector<std::uint32_t>>{};
    if (parts.empty() && depth < kMaxSplitDepth) {
      // Or hang on to a trunk: drop the columns under points just above the band and look
      // at what stays connected.
      std::vector<std::uint32_t> rest;
      for (std::uint32_t q : pts) {
        if (!c.above.count(column_key(c.x[q], c.y[q], c.p.voxel))) rest.push_back(q);
      }
      if (rest.size() >= c.p.min_points && rest.size() < pts.size()) {
        parts = cluster_points(rest, c.x, c.y, c.z, c.p.voxel, Clustering::kGrid);
      }
    }
    if (parts.empty()) {
      ++c.out.rejected_canopy;
      return;
    }
    ++c.out.splits;
    for (auto& part : parts) examine(c, std::move(part), depth + 1);
    return;
  }
  // Examines the pieces of a row split or a trim (rows.h) and what no roof is near (a wall, a
  // hedge's far end) as objects of their own.
  auto examine_row = [&](RowSplit& row) {
    ++(row.trimmed ? c.out.trims : c.out.row_splits);
    ++c.in_row;
    c.in_trim += row.trimmed;
    // With object_field the rest is cut off from the pieces whether examined or not: an
    // examination of its own (Objects::examined), which its parts' examinations below renumber;
    // a trim's (one piece: the vehicle) is recorded as its leftover (Objects::trim_rests).
    TrimRest marks;
    if (numbered) {
      marks.rest = c.examinations++;
      for (std::uint32_t q : row.rest) c.out.examined[q] = marks.rest;
      marks.piece = c.examinations;
    }
    for (auto& piece : row.pieces) examine(c, std::move(piece), depth + 1);
    marks.rest_parts_begin = c.examinations;
    if (row.rest.size() >= p.min_points) {
      for (auto& part : cluster_points(row.rest, c.x, c.y, c.z, p.voxel, Clustering::kGrid))
        examine(c, std::move(part), depth + 1);
    } else if (!row.rest.empty()) {
      ++c.out.rejected_small;
    }
    marks.rest_parts_end = c.examinations;
    if (numbered && row.trimmed) c.out.trim_rests.push_back(marks);
    --c.in_row;
    c.in_trim -= row.trimmed;
  };
  RowSplit trim;  // one vehicle with something beside it: trimmed only if accepted whole (below)
  if (p.split_rows && depth < kMaxSplitDepth && (o.fp.length > kRowLength || o.fp.width > kRowWidth)) {
    // A row of parked vehicles merged by the voxel: one piece per roof (rows.h, detect.md §9).
    RowSplit row = split_row(pts, c.x, c.y, c.h, o.fp, p.row_roof_height, p.row_tolerance, p.row_max_height,
                             p.row_trim * p.row_tolerance);
    if (row.trimmed) {
      trim = std::move(row);
    } else if (!row.pieces.empty()) {
      examine_row(row);
      return;
    }
  }
  const bool too_long = o.fp.length > p.max_length, too_wide = o.fp.width > p.max_width;
  // Wider than two narrow vehicles, or oversized: objects that only touch come apart with a
  // finer voxel.
  const bool two_wide = o.fp.width > 2 * p.min_width + 1.0;
  if ((too_long || too_wide || two_wide) && depth < kMaxSplitDepth) {
    auto parts = finer_parts(c, pts, 0.1, p.min_split_share);
    // Only wider than two narrow vehicles: the parts must be vehicles side by side.
    if (!parts.empty() && p.min_split_share > 0 && two_wide && !too_long && !too_wide &&
        !side_by_side(c, parts, Vector2d(-o.fp.axis.y(), o.fp.axis.x())))
      parts.clear();
    if (!parts.empty()) {
      ++c.out.splits;
      for (auto& part : parts) examine(c, std::move(part), depth + 1);
      return;
    }
  }
  // Cuts the object at a clear valley across axis `a` (pieces at least `min_part` wide) and
  // examines both sides; false when there is no such valley.
  auto split_at_valley = [&](const Vector2d& a, double min_part, double min_gap) {
    const double cut = valley_cut(c, pts, a, min_part, min_gap);
    if (std::isnan(cut)) return false;
    std::vector<std::uint32_t> lo, hi;
    for (std::uint32_t q : pts) (Vector2d(c.x[q], c.y[q]).dot(a) < cut ? lo : hi).push_back(q);
    ++c.out.splits;
    examine(c, std::move(lo), depth + 1);
    examine(c, std::move(hi), depth + 1);
    return true;
  };
  if (two_wide && !too_long && depth < kMaxSplitDepth) {
    // Side by side and touching: a valley across the width.
    if (split_at_valley(Vector2d(-o.fp.axis.y(), o.fp.axis.x()), p.min_width, p.side_gap * p.voxel)) return;
  }
  if (too_long || too_wide) {
    // Oversized: cut at a clear valley across the oversized axis.
    if (depth < kMaxSplitDepth) {
      const Vector2d a = too_wide ? Vector2d(-o.fp.axis.y(), o.fp.axis.x()) : o.fp.axis;
      if (split_at_valley(a, too_wide ? p.min_width : p.min_length, 0.0)) return;
    }
    // No clean split: a vehicle with a bush against it stays a candidate (recall first) when
    // it is at most a quarter beyond the ranges.
    if (o.fp.length > 1.25 * p.max_length || o.fp.width > 1.25 * p.max_width) {
      ++c.out.rejected_large;
      return;
    }
  }
  // Accepted whole, but two bodies end to end with the ground seen between them (detect.md §19).
  if (p.end_gap > 0 && depth < kMaxSplitDepth) {
    const double cut = end_gap_cut(c, pts, o.fp.axis, p.end_gap * p.voxel);
    if (!std::isnan(cut)) {
      std::vector<std::uint32_t> lo, hi;
      for (std::uint32_t q : pts) (Vector2d(c.x[q], c.y[q]).dot(o.fp.axis) < cut ? lo : hi).push_back(q);
      ++c.out.splits;
      examine(c, std::move(lo), depth + 1);
      examine(c, std::move(hi), depth + 1);
      return;
    }
  }
  // Accepted whole, but one roof of vehicle length with parts beyond its reach: the vehicle and
  // the rest (detect.md §12). After the other splits, which part objects that touch in 3-D.
  if (!trim.pieces.empty()) {
    examine_row(trim);
    return;
  }
  o.points = std::move(pts);
  o.row_piece = c.in_row > 0;
  o.trim_piece = c.in_trim > 0;
  o.origins = {c.origin};
  o.lineage = c.lineage;  // empty without object_field
  c.out.accepted.push_back(std::move(o));
}

// Pieces of one vehicle (detect.md §10): the cab and the low deck of a tractor unit are apart in
// 3-D (its back wall returned little) but touch in the top view. Two accepted objects are merged
// when, in the top view, their points come within `merge_gap` voxels of each other, they lie end
// to end along the union's long axis (overlapping by at most half the shorter one: not a bush
// over a car), the union is no wider than the wider piece + kMergeWiden (in line: not a bush or a
// vehicle beside it) and fits the vehicle ranges. Pieces of a row split (rows.h) stay apart: the
// row rule decided them; but the row rule decides only between vehicles under row_max_height
// (detect.md §11), so with merge_tall_rows a pair of which one rises above it (a tractor unit's
// cab that a row split parted from its deck) is merged like any other (detect.md §13). Pieces
// of a trim stay apart whatever their height: the trim decided that the rest is not the vehicle.
// Repeated until no pair merges; pairs in the order found.
void merge_pieces(Context& c) {
  const Params& p = c.p;
  if (p.merge_gap <= 0) return;
  const double reach = p.merge_gap * p.voxel;
  auto& objs = c.out.accepted;
  auto tall = [&](const Object& o) {
    return p.merge_tall_rows && p.row_max_height > 0 && o.height > p.row_max_height;
  };
  // With join_stacked the row and trim rules keep apart only pieces of one cluster: a cluster
  // apart from it in 3-D (a cab over a deck's end whose back wall the sensor did not see) was
  // not before them (detect.md §16).
  auto decided = [&](const Object& a, const Object& b) {
    if (!p.join_stacked) return true;
    for (std::size_t k : a.origins)
      if (std::find(b.origins.begin(), b.origins.end(), k) != b.origins.end()) return true;
    return false;
  };
  auto apart = [&](const Object& a, const Object& b) {
    return decided(a, b) &&
           (a.trim_piece || b.trim_piece || ((a.row_piece || b.row_piece) && !tall(a) && !tall(b)));
  };
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t a = 0; a < objs.size() && !merged; ++a) {
      for (std::size_t b = a + 1; b < objs.size() && !merged; ++b) {
        const Footprint& fa = objs[a].fp;
        const Footprint& fb = objs[b].fp;
        if (apart(objs[a], objs[b])) continue;
        // Rectangles farther apart than the gap cannot touch.
        if ((fa.centre - fb.centre).norm() >
            0.5 * (std::hypot(fa.length, fa.width) + std::hypot(fb.length, fb.width)) + reach)
          continue;
        std::vector<std::uint32_t> both = objs[a].points;
        both.insert(both.end(), objs[b].points.begin(), objs[b].points.end());
        const Footprint u = plan_footprint(c.x, c.y, both);
        if (u.length > p.max_length || u.width > p.max_width) continue;
        if (u.width > std::max(fa.width, fb.width) + kMergeWiden) continue;
        if (overlap_half(span_along(c, objs[a].points, u.axis), span_along(c, objs[b].points, u.axis)))
          continue;
        if (!touch_in_plan(c.x, c.y, objs[a].points, objs[b].points, reach)) continue;
        std::sort(both.begin(), both.end());
        objs[a].points = std::move(both);
        objs[a].fp = u;
        objs[a].height = std::max(objs[a].height, objs[b].height);
        objs[a].row_piece = objs[a].row_piece || objs[b].row_piece;
        objs[a].trim_piece = objs[a].trim_piece || objs[b].trim_piece;
        objs[a].origins.insert(objs[a].origins.end(), objs[b].origins.begin(), objs[b].origins.end());
        objs[a].lineage.insert(objs[a].lineage.end(), objs[b].lineage.begin(), objs[b].lineage.end());
        objs.erase(objs.begin() + long(b));
        ++c.out.merges;
        merged = true;
      }
    }
  }
}

// Clusters stacked in height (detect.md §16): seen from above, a vehicle's vertical faces (a
// cab's back wall, the sides of an earthmover's cab) return next to nothing, so its parts at
// different heights (a cab roof beside a deck, a cab top between the bonnet and the rear) are
// clusters of their own in (x, y, height) that touch only in the top view. Two clusters are
// joined before they are examined when their points come within `reach` of each other in the
// top view, they lie beside each other rather than one over the other (at most
// kStackOverlay of the smaller one's top-view cells also hold points of the other: a contact
// line, not a crown or a branch over a car), and their union is in line (no wider than the
// wider one + kMergeWiden) and fits the vehicle ranges. Repeated until no pair joins.
void join_stacked(Context& c, std::vector<std::vector<std::uint32_t>>& clusters) {
  const Params& p = c.p;
  const double reach = p.merge_gap * p.voxel;
  if (reach <= 0) return;
  struct Info {
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;  // the top view's bounding box
    double height = 0;                                        // its highest point above the DTM
    bool has_fp = false;
    Footprint fp;
  };
  std::vector<Info> info(clusters.size());
  auto bound = [&](Info& in, const std::vector<std::uint32_t>& pts) {
    for (std::uint32_t q : pts) {
      in.x0 = std::min(in.x0, c.x[q]);
      in.x1 = std::max(in.x1, c.x[q]);
      in.y0 = std::min(in.y0, c.y[q]);
      in.y1 = std::max(in.y1, c.y[q]);
      in.height = std::max(in.height, double(c.h[q]));
    }
  };
  // A cluster reaching the band's top voxel layer may go on above it (a crown, a wall, a hedge
  // under a tree: continues_upward's layer); its height is not a vehicle part's, so it is not
  // joined (on ahn3_delft_1 four cars were joined to such 4.5 m clusters, detect.md §16).
  const double top = p.max_height - p.voxel;
  auto joinable = [&](std::size_t k) { return clusters[k].size() >= p.min_points && info[k].height < top; };
  auto fp = [&](std::size_t k) -> const Footprint& {
    if (!info[k].has_fp) {
      info[k].fp = plan_footprint(c.x, c.y, clusters[k]);
      info[k].has_fp = true;
    }
    return info[k].fp;
  };
  for (std::size_t k = 0; k < clusters.size(); ++k) bound(info[k], clusters[k]);
  // Passes over every pair until none joins; a cluster that grew is compared again with the
  // rest of its pass.
  for (bool joined = true; joined;) {
    joined = false;
    for (std::size_t a = 0; a < clusters.size(); ++a) {
      if (!joinable(a)) continue;
      for (std::size_t b = a + 1; b < clusters.size(); ++b) {
        if (!joinable(b)) continue;
        const Info& ia = info[a];
        const Info& ib = info[b];
        if (ia.x0 > ib.x1 + reach || ib.x0 > ia.x1 + reach || ia.y0 > ib.y1 + reach || ib.y0 > ia.y1 + reach)
          continue;
        // A cluster beyond the ranges alone (a crown) is not a vehicle's part.
        const Footprint& fa = fp(a);
        const Footprint& fb = fp(b);
        if (fa.length > p.max_length || fa.width > p.max_width || fb.length > p.max_length ||
            fb.width > p.max_width)
          continue;
        if (!touch_in_plan(c.x, c.y, clusters[a], clusters[b], reach)) continue;
        std::vector<std::uint32_t> both = clusters[a];
        both.insert(both.end(), clusters[b].begin(), clusters[b].end());
        const Footprint u = plan_footprint(c.x, c.y, both);
        if (u.length > p.max_length || u.width > p.max_width) continue;
        if (u.width > std::max(fa.width, fb.width) + kMergeWiden) continue;
        // Beside, not over: the smaller cluster's top-view cells that also hold the other's.
        const bool small_a = clusters[a].size() <= clusters[b].size();
        if (over_in_plan(c.x, c.y, small_a ? clusters[a] : clusters[b], small_a ? clusters[b] : clusters[a],
                         reach))
          continue;
        clusters[a] = std::move(both);
        bound(info[a], clusters[b]);
        info[a].fp = u;
        info[a].has_fp = true;
        clusters.erase(clusters.begin() + long(b));
        info.erase(info.begin() + long(b));
        ++c.out.stacked;
        joined = true;
        b = a;  // the grown cluster against the rest again
      }
    }
  }
}

}  // namespace

Objects find_objects(const LocalFrame& l, const std::vector<float>& height, const Params& params,
                     const std::string& name) {
  const std::size_t n = l.x.size();
  std::vector<std::uint32_t> band;
  for (std::size_t i = 0; i < n; ++i) {
    if (height[i] >= params.min_object_height && height[i] <= params.max_height)
      band.push_back(std::uint32_t(i));
  }
  Objects out;
  out.band_points = band.size();
  if (params.object_field) out.examined.assign(n, -1);
  std::vector<double> hz(n);  // clustering in (x, y, height): the band is a flat slab
  for (std::size_t i = 0; i < n; ++i) hz[i] = height[i];
  Context ctx{params, l.x, l.y, hz, height, out, {}, {}, 0, 0, 0, {}, 0, {}};
  for (std::size_t i = 0; i < n; ++i) {
    if (height[i] > params.max_height && height[i] <= params.max_height + 2 * params.voxel) {
      ctx.above.emplace(column_key(l.x[i], l.y[i], params.voxel), 1);
    }
  }
  if (params.end_gap > 0) {
    for (std::size_t i = 0; i < n; ++i)
      if (height[i] < params.min_object_height)
        ctx.ground[column_key(l.x[i], l.y[i], params.voxel)].push_back(std::uint32_t(i));
  }
  try {
    auto clusters = cluster_points(band, l.x, l.y, hz, params.voxel, params.clustering);
    out.clusters = clusters.size();
    if (params.join_stacked) join_stacked(ctx, clusters);
    for (std::size_t k = 0; k < clusters.size(); ++k) {
      ctx.origin = k;
      examine(ctx, std::move(clusters[k]), 0);
    }
    merge_pieces(ctx);
    out.fragments = merge_fragments(l.x, l.y, height, params, ctx.fragments, out.accepted);
  } catch (const VoxelOverflow& e) {
    throw DataError(name, "the points between --min-object-height and --max-height span " +
                              format_number("%.6g", e.extent) + " m, more than " +
                              std::to_string(kVoxelMask - 1) + " clustering voxels along an axis of --voxel " +
                              format_number("%g", params.voxel) + " m: raise --voxel (or crop the tile)");
  }
  return out;
}

}  // namespace canopy::detect
