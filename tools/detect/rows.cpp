#include "detect/rows.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include "detect/clustering.h"
#include "detect/footprint.h"

namespace canopy::detect {
namespace {

using Eigen::Vector2d;

// The top view of `pts` (rows) as a PCL cloud at z = 0.
pcl::PointCloud<pcl::PointXYZ>::Ptr top_view(const std::vector<std::uint32_t>& pts,
                                             const std::vector<double>& x, const std::vector<double>& y) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr c(new pcl::PointCloud<pcl::PointXYZ>);
  c->resize(pts.size());
  for (std::size_t n = 0; n < pts.size(); ++n)
    (*c)[n] = pcl::PointXYZ(float(x[pts[n]]), float(y[pts[n]]), 0.0f);
  return c;
}

Footprint rectangle_of(const std::vector<std::uint32_t>& pts, const std::vector<double>& x,
                       const std::vector<double>& y) {
  std::vector<Vector2d> xy(pts.size());
  for (std::size_t n = 0; n < pts.size(); ++n) xy[n] = Vector2d(x[pts[n]], y[pts[n]]);
  return min_area_rectangle(xy);
}

// The rectangle of `pts` with its long side along `axis` or across it (unit).
Footprint rectangle_along(const std::vector<std::uint32_t>& pts, const std::vector<double>& x,
                          const std::vector<double>& y, const Vector2d& axis) {
  const Vector2d across(-axis.y(), axis.x());
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  for (std::uint32_t q : pts) {
    const Vector2d p(x[q], y[q]);
    u0 = std::min(u0, p.dot(axis));
    u1 = std::max(u1, p.dot(axis));
    v0 = std::min(v0, p.dot(across));
    v1 = std::max(v1, p.dot(across));
  }
  Footprint f;
  f.centre = axis * (u0 + u1) / 2 + across * (v0 + v1) / 2;
  const bool along = u1 - u0 >= v1 - v0;
  f.axis = along ? axis : across;
  f.length = std::max(u1 - u0, v1 - v0);
  f.width = std::min(u1 - u0, v1 - v0);
  return f;
}

// The parts of `pts` whose top views lie within `tolerance` of each other (PCL's Euclidean
// clustering on the points at z = 0).
std::vector<std::vector<std::uint32_t>> top_view_clusters(const std::vector<std::uint32_t>& pts,
                                                          const std::vector<double>& x,
                                                          const std::vector<double>& y, double tolerance) {
  if (pts.empty()) return {};
  const auto cloud = top_view(pts, x, y);
  const std::vector<pcl::PointIndices> found = euclidean_clusters(cloud, tolerance);
  std::vector<std::vector<std::uint32_t>> parts;
  for (const auto& c : found) {
    std::vector<std::uint32_t> part;
    for (int i : c.indices) part.push_back(pts[std::size_t(i)]);
    parts.push_back(std::move(part));
  }
  return parts;
}

bool fits_one_roof(const Footprint& f) { return f.length <= kRowRoofLength && f.width <= kRowRoofWidth; }

// A roof's reach: the points of its vehicle lie within `along` of the roof along the vehicle's
// axis and `across` beside it.
struct Reach {
  Vector2d centre, axis;           // the vehicle's axis
  double half_along, half_across;  // the roof's half extents along and across it
  double along, across;            // the reach beyond them
};

// True when the top view of point q lies within the reach r.
bool within(const Reach& r, const std::vector<double>& x, const std::vector<double>& y, std::uint32_t q) {
  const Vector2d d = Vector2d(x[q], y[q]) - r.centre;
  const double du = std::max(0.0, std::abs(d.dot(r.axis)) - r.half_along);
  const double dv = std::max(0.0, std::abs(d.dot(Vector2d(-r.axis.y(), r.axis.x()))) - r.half_across);
  return du <= r.along && dv <= r.across;
}

// One vehicle's roof in an object: the object's parts in the top view at `gap` (PCL's Euclidean
// clustering of every point at z = 0) that hold a point of the roof, or lie below the roof band
// (under `roof_height`) within its reach along the vehicle and kTrimSide beside the roof (a
// bonnet or boot whose returns are apart from the roof's: a windscreen that returned nothing),
// are the vehicle; the other parts are the rest. No piece when there is no rest (nothing to
// trim).
RowSplit trim_to_roof(const std::vector<std::uint32_t>& pts, const std::vector<double>& x,
                      const std::vector<double>& y, const std::vector<float>& h,
                      std::vector<std::uint32_t> roof, Reach reach, double roof_height, double gap) {
  std::sort(roof.begin(), roof.end());
  reach.across = kTrimSide;
  RowSplit out;
  std::vector<std::uint32_t> vehicle;
  for (auto& part : top_view_clusters(pts, x, y, gap)) {
    const bool keep =
        std::all_of(part.begin(), part.end(),
                    [&](std::uint32_t q) { return h[q] < roof_height && within(reach, x, y, q); }) ||
        std::any_of(part.begin(), part.end(),
                    [&](std::uint32_t q) { return std::binary_search(roof.begin(), roof.end(), q); });
    auto& to = keep ? vehicle : out.rest;
    to.insert(to.end(), part.begin(), part.end());
  }
  if (out.rest.empty() || vehicle.empty()) return {};
  std::sort(vehicle.begin(), vehicle.end());
  std::sort(out.rest.begin(), out.rest.end());
  out.pieces.push_back(std::move(vehicle));
  out.trimmed = true;
  return out;
}

}  // namespace

double row_tolerance_for_density(double d) {
  return d > 0 ? std::clamp(kRowSpacings / std::sqrt(d), 0.3, 0.6) : 0.6;
}

RowSplit split_row(const std::vector<std::uint32_t>& pts, const std::vector<double>& x,
                   const std::vector<double>& y, const std::vector<float>& h, const Footprint& row,
                   double roof_height, double tolerance, double max_height, double trim_gap) {
  const Vector2d row_axis = row.axis;
  RowSplit out;
  std::vector<std::uint32_t> band;
  for (std::uint32_t q : pts) {
    if (h[q] >= roof_height && h[q] <= kRowRoofTop) band.push_back(q);
  }
  if (band.size() < 2 * kRowRoofPoints) return out;
  // The roof band's parts in the top view; a part too wide or too long for one roof (two roofs
  // joined by a mirror, a sign, a low branch) is looked at higher up the band, where the
  // bodies narrow: kRowRaise at a time, kRowRaises times.
  std::vector<std::vector<std::uint32_t>> parts;
  std::vector<std::pair<std::vector<std::uint32_t>, int>> todo{{band, 0}};
  while (!todo.empty()) {
    auto [set, raised] = std::move(todo.back());
    todo.pop_back();
    auto found = top_view_clusters(set, x, y, tolerance);
    for (auto& part : found) {
      if (raised < kRowRaises && part.size() >= 2 * kRowRoofPoints && !fits_one_roof(rectangle_of(part, x, y))) {
        const double above = roof_height + (raised + 1) * kRowRaise;
        std::vector<std::uint32_t> higher;
        for (std::uint32_t q : part) {
          if (h[q] >= above) higher.push_back(q);
        }
        const auto split = top_view_clusters(higher, x, y, tolerance);
        std::size_t big = 0;
        for (const auto& sp : split) big += sp.size() >= kRowRoofPoints;
        if (big >= 2) {
          todo.emplace_back(std::move(higher), raised + 1);
          continue;
        }
      }
      parts.push_back(std::move(part));
    }
  }
  if (parts.size() < 2 && trim_gap <= 0) return out;  // one part: one roof at most
  // Fragments of one roof (a windscreen or a dark panel returned nothing): join the two parts
  // whose union has the smallest rectangle while it fits one roof, until none does. Only parts
  // whose bounding boxes together span at most a roof's diagonal can fit (most pairs).
  const double reach = std::hypot(kRowRoofLength, kRowRoofWidth);
  std::vector<Eigen::AlignedBox2d> box(parts.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    for (std::uint32_t q : parts[i]) box[i].extend(Vector2d(x[q], y[q]));
  }
  std::vector<char> alive(parts.size(), 1);
  struct Pair {
    double area;
    std::size_t i, j;
  };
  std::vector<Pair> fit;  // the pairs whose union fits one roof
  auto consider = [&](std::size_t i, std::size_t j) {
    if (box[i].merged(box[j]).sizes().maxCoeff() > reach) return;
    std::vector<std::uint32_t> u = parts[i];
    u.insert(u.end(), parts[j].begin(), parts[j].end());
    const Footprint f = rectangle_of(u, x, y);
    if (fits_one_roof(f)) fit.push_back({f.length * f.width, std::min(i, j), std::max(i, j)});
  };
  for (std::size_t i = 0; i < parts.size(); ++i) {
    for (std::size_t j = i + 1; j < parts.size(); ++j) consider(i, j);
  }
  while (!fit.empty()) {
    const auto best = std::min_element(fit.begin(), fit.end(), [](const Pair& a, const Pair& b) {
      return a.area < b.area || (a.area == b.area && (a.i < b.i || (a.i == b.i && a.j < b.j)));
    });
    const std::size_t i = best->i, j = best->j;
    parts[i].insert(parts[i].end(), parts[j].begin(), parts[j].end());
    box[i].extend(box[j]);
    parts[j].clear();
    alive[j] = 0;
    fit.erase(std::remove_if(fit.begin(), fit.end(),
                             [&](const Pair& p) { return p.i == i || p.j == i || p.i == j || p.j == j; }),
              fit.end());
    for (std::size_t k = 0; k < parts.size(); ++k) {
      if (k != i && alive[k]) consider(i, k);
    }
  }
  // Two roofs a sampling hole apart (scan lines over a large vehicle's flat top, kRowHole
  // tolerances or less) are one: between two vehicles the gap holds the lower parts of their
  // bodies (bonnets, boots, doors), so some point of the object below the band lies within
  // half the gap (at least a tolerance) of the gap's middle.
  {
    std::vector<std::uint32_t> low;
    for (std::uint32_t q : pts) {
      if (h[q] < roof_height) low.push_back(q);
    }
    std::vector<std::size_t> group(parts.size());
    for (std::size_t i = 0; i < parts.size(); ++i) group[i] = i;
    auto find = [&](std::size_t a) {
      while (group[a] != a) a = group[a] = group[group[a]];
      return a;
    };
    const double hole = kRowHole * tolerance;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      for (std::size_t j = i + 1; j < parts.size(); ++j) {
        if (parts[i].empty() || parts[j].empty() || find(i) == find(j)) continue;
        if ((box[i].exteriorDistance(box[j])) > hole) continue;
        double g2 = std::numeric_limits<double>::infinity();
        Vector2d mid = Vector2d::Zero();
        for (std::uint32_t a : parts[i]) {
          for (std::uint32_t b : parts[j]) {
            const double d2 = (Vector2d(x[a], y[a]) - Vector2d(x[b], y[b])).squaredNorm();
            if (d2 < g2) {
              g2 = d2;
              mid = (Vector2d(x[a], y[a]) + Vector2d(x[b], y[b])) / 2;
            }
          }
        }
        if (std::sqrt(g2) > hole) continue;
        const double r = std::max(std::sqrt(g2) / 2, tolerance);
        bool lower = false;
        for (std::uint32_t q : low) {
          if ((Vector2d(x[q], y[q]) - mid).squaredNorm() <= r * r) {
            lower = true;
            break;
          }
        }
        if (!lower) group[find(j)] = find(i);
      }
    }
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const std::size_t g = find(i);
      if (g == i) continue;
      parts[g].insert(parts[g].end(), parts[i].begin(), parts[i].end());
      parts[i].clear();
    }
  }
  // The object's points above the tallest vehicle of a row (max_height; none when 0).
  std::vector<std::uint32_t> high;
  if (max_height > 0) {
    for (std::uint32_t q : pts) {
      if (h[q] > max_height) high.push_back(q);
    }
  }
  // Roofs: parts with enough points; a split needs two of vehicle length under which the object
  // stays below max_height. A part with kRowRoofPoints of the object's points above max_height
  // over its rectangle (grown by the tolerance) is the band's slice through a taller vehicle (a
  // tractor unit's cab and its deck, a wheel loader's cab and its bucket: their band parts are
  // apart and have lower parts between them, like two cars), not the roof of a car or van.
  std::vector<std::vector<std::uint32_t>> roofs;
  std::size_t short_roofs = 0, in_short = 0;  // roofs of vehicle length and their points
  std::size_t low_roofs = 0;                  // of those, roofs with the object below max_height over them
  std::size_t short_roof = 0;                 // the index in roofs of the last of vehicle length
  for (auto& part : parts) {
    if (part.size() < kRowRoofPoints) continue;  // and the parts joined to others
    const Footprint f = rectangle_of(part, x, y);
    if (f.length <= kRowRoofMax) {
      short_roof = roofs.size();
      ++short_roofs;
      in_short += part.size();
      const Vector2d across(-f.axis.y(), f.axis.x());
      std::size_t over = 0;
      for (std::uint32_t q : high) {
        const Vector2d d = Vector2d(x[q], y[q]) - f.centre;
        over += std::abs(d.dot(f.axis)) <= f.length / 2 + tolerance &&
                std::abs(d.dot(across)) <= f.width / 2 + tolerance;
      }
      low_roofs += over < kRowRoofPoints;
    }
    roofs.push_back(std::move(part));
  }
  // A row is mostly roofs: hedges, shrubs and crowns in the band leave irregular parts, of
  // which a few may be roof-sized.
  const bool mostly_roofs = double(in_short) >= kRowRoofShare * double(band.size());
  // One low roof of vehicle length that holds the band: one vehicle with something lower beside
  // it (a bicycle stand, a planter, a low hedge, a neighbour's bonnet) that the voxel joined to
  // it. It is trimmed off where the top view has a gap of trim_gap (detect.md §12).
  const bool trim = trim_gap > 0 && low_roofs == 1 && short_roofs == 1 && mostly_roofs;
  if (!trim && (low_roofs < 2 || !mostly_roofs)) return out;
  if (trim) {
    // The one roof of vehicle length; the other parts of the band are not roofs.
    std::vector<std::vector<std::uint32_t>> one(1);
    one[0] = std::move(roofs[short_roof]);
    roofs.swap(one);
  }
  // Vehicles in a row park along it or across it: a roof's axis within kRowSnap of either is
  // taken as that (a sparse roof's own rectangle turns by a few degrees, and its reach then
  // takes a wall beside the car).
  std::vector<Footprint> rect;
  for (const auto& roof : roofs) {
    Footprint f = rectangle_of(roof, x, y);
    const double c = std::abs(f.axis.dot(row_axis));
    if (c >= std::cos(kRowSnap) || c <= std::sin(kRowSnap)) f = rectangle_along(roof, x, y, row_axis);
    rect.push_back(f);
  }
  // Each roof's reach: kRowAssign along its vehicle's axis, kRowSide across it. A roof about as
  // long as wide does not say which way its vehicle points: the row does when it is as wide as
  // a vehicle is long (nose-in, vehicles across it) or narrower than kRowWidth (vehicles along
  // it); else kRowAssign both ways.
  std::vector<Reach> reach_of;
  const Vector2d row_across(-row.axis.y(), row.axis.x());
  for (const Footprint& f : rect) {
    Reach r{f.centre, f.axis, f.length / 2, f.width / 2, kRowAssign, kRowSide};
    if (f.length < kRowElongated * f.width) {
      if (row.width >= kRowNoseIn || row.width <= kRowWidth) {
        const Vector2d car = row.width >= kRowNoseIn ? row_across : row.axis;
        if (std::abs(car.dot(f.axis)) < 0.5) std::swap(r.half_along, r.half_across);
        r.axis = car;
      } else {
        r.across = kRowAssign;
      }
    }
    reach_of.push_back(r);
  }
  if (trim) return trim_to_roof(pts, x, y, h, roofs.front(), reach_of.front(), roof_height, trim_gap);
  // Every point of the object to the roof nearest it in the top view within that reach.
  out.pieces.resize(roofs.size());
  for (std::uint32_t q : pts) {
    const Vector2d p(x[q], y[q]);
    double best = std::numeric_limits<double>::infinity();
    std::size_t at = 0;
    for (std::size_t k = 0; k < reach_of.size(); ++k) {
      const Reach& r = reach_of[k];
      const Vector2d d = p - r.centre;
      const double du = std::max(0.0, std::abs(d.dot(r.axis)) - r.half_along);
      const double dv = std::max(0.0, std::abs(d.dot(Vector2d(-r.axis.y(), r.axis.x()))) - r.half_across);
      if (du > r.along || dv > r.across) continue;
      const double dist = std::hypot(du, dv);
      if (dist < best) {
        best = dist;
        at = k;
      }
    }
    (std::isfinite(best) ? out.pieces[at] : out.rest).push_back(q);
  }
  return out;
}

}  // namespace canopy::detect
