// classify's object: gap bridging (classify.md §21, --bridge), joining the clusters that a
// vehicle's own no-return gaps (windscreen, rear window) split off it; parts stacked in height
// (classify.md §25, --join-stacked).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "canopy/common/error.h"
#include "classify/features.h"

namespace canopy::classify {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// classify.md §25 (object_of with `join_stacked`): joins to the object (`in`) each cluster of
// `label` that meets it within `link` in the top view, beside it (top-view cells of `link`: at most
// kStackOverlay of the smaller one's cells hold points of the other) and in line (across x the
// union at most kStackInLine wider than the wider one) and holds at least kStackPart of the
// object's points, until none joins.
constexpr double kStackOverlay = 0.25;  // detect.md §16's kStackOverlay
constexpr double kStackInLine = 0.3;    // detect.md §10's in-line test (m)
// A part is a surface the sensor sampled: at least this share of the object's points (a cab top
// over an earthmover's body holds some 15-25%, a semi-tractor's deck 30-60%); a tuft of grass, a
// twig or a few stray returns at the edge do not join.
constexpr double kStackPart = 0.1;

}  // namespace

void join_beside(const std::vector<Eigen::Vector3d>& pts, const std::vector<std::size_t>& label, double link,
                 std::vector<char>& in) {
  auto key2 = [&](double x, double y) { return cell_key(cell_of(x, link), cell_of(y, link)); };
  for (bool joined = true; joined;) {
    joined = false;
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> grid;  // the object's points
    std::unordered_set<std::uint64_t> cells;
    double ow0 = kInf, ow1 = -kInf;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (!in[i]) continue;
      const std::uint64_t k = key2(pts[i].x(), pts[i].y());
      grid[k].push_back(i);
      cells.insert(k);
      ow0 = std::min(ow0, pts[i].y());
      ow1 = std::max(ow1, pts[i].y());
    }
    std::map<std::size_t, std::vector<std::size_t>> others;  // by root: a fixed order
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (!in[i]) others[label[i]].push_back(i);
    }
    std::size_t object_size = 0;
    for (char x : in) object_size += x != 0;
    for (const auto& [l, members] : others) {
      if (static_cast<double>(members.size()) < kStackPart * static_cast<double>(object_size)) continue;
      bool touch = false;
      std::unordered_set<std::uint64_t> own;
      double w0 = kInf, w1 = -kInf;
      for (std::size_t i : members) {
        own.insert(key2(pts[i].x(), pts[i].y()));
        w0 = std::min(w0, pts[i].y());
        w1 = std::max(w1, pts[i].y());
        const std::int64_t cx = cell_of(pts[i].x(), link), cy = cell_of(pts[i].y(), link);
        for (std::int64_t dx = -1; dx <= 1 && !touch; ++dx) {
          for (std::int64_t dy = -1; dy <= 1 && !touch; ++dy) {
            const auto it = grid.find(cell_key(cx + dx, cy + dy));
            if (it == grid.end()) continue;
            for (std::size_t j : it->second) {
              if (std::hypot(pts[j].x() - pts[i].x(), pts[j].y() - pts[i].y()) <= link) {
                touch = true;
                break;
              }
            }
          }
        }
      }
      if (!touch) continue;
      std::size_t shared = 0;
      for (std::uint64_t k : own) shared += cells.count(k);
      if (static_cast<double>(shared) > kStackOverlay * static_cast<double>(std::min(own.size(), cells.size())))
        continue;  // over or under the object: a crown, a branch, a bush over it
      if (std::max(w1, ow1) - std::min(w0, ow0) > std::max(w1 - w0, ow1 - ow0) + kStackInLine) continue;
      for (std::size_t i : members) in[i] = 1;
      joined = true;
      break;
    }
  }
}

// classify.md §21: joins to the object (`in`, the clusters of `label` rooted at `best`) the
// clusters that a vehicle's own gaps split off it. A windscreen or rear window returns nothing
// (glass; dark paint too), so once the link is shorter than the glass (≈ 0.5-1.0 m in the top
// view) a car falls apart into cabin, bonnet and boot along its long axis. Such a gap is a
// shadow: neither the vehicle nor the ground under it returned. The space between two objects
// returns the ground. A cluster joins when it lies within the object's extent across x
// (detect's long axis) + `link` (in line with it, not beside it), its top is at most the
// object's top and at least half of it (a bonnet or boot under the roof, not grass, a kerb or
// a crown above), its nearest point is within `bridge` of the object's in the top view, the
// strip between them along x (across: where both extend) holds fewer than kGapGround of the
// ground returns the crop's ground density would put there, and the joined object is at most
// `bridge_length` long. Nearest cluster first, until none joins. With `min_share` (classify.md
// §27) a cluster also needs at least that share of the object's points: a bonnet or boot is a
// part the sensor sampled, a few stray returns in line with the car are not. Each strip crossed
// goes to `shadows` with the share of it that returned nothing.
void bridge_gaps(const std::vector<Eigen::Vector3d>& pts, const std::vector<std::size_t>& label,
                 std::size_t best, const std::vector<Eigen::Vector2d>& ground, double ground_density,
                 double link, double bridge, double bridge_length, std::vector<char>& in, double min_share,
                 std::vector<Shadow>* shadows) {
  struct Piece {
    double x0 = kInf, x1 = -kInf, y0 = kInf, y1 = -kInf, top = -kInf;
    std::vector<std::size_t> members;
  };
  std::unordered_map<std::size_t, Piece> pieces;
  std::vector<std::size_t> roots;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    auto [it, fresh] = pieces.try_emplace(label[i]);
    if (fresh) roots.push_back(label[i]);
    Piece& q = it->second;
    q.x0 = std::min(q.x0, pts[i].x());
    q.x1 = std::max(q.x1, pts[i].x());
    q.y0 = std::min(q.y0, pts[i].y());
    q.y1 = std::max(q.y1, pts[i].y());
    q.top = std::max(q.top, pts[i].z());
    q.members.push_back(i);
  }
  Piece object = pieces[best];
  std::vector<char> joined(pts.size(), 0);  // per root
  joined[best] = 1;
  const double bridge2 = bridge * bridge;
  for (;;) {
    std::size_t pick = 0;
    double pick_gap2 = kInf;
    for (std::size_t r : roots) {
      if (joined[r]) continue;
      const Piece& q = pieces[r];
      const bool within = q.y0 >= object.y0 - link && q.y1 <= object.y1 + link;
      const bool level = q.top <= object.top && q.top >= 0.5 * object.top;
      const bool short_enough = std::max(q.x1, object.x1) - std::min(q.x0, object.x0) <= bridge_length;
      const bool part =
          static_cast<double>(q.members.size()) >= min_share * static_cast<double>(object.members.size());
      if (!within || !level || !short_enough || !part) continue;
      if (q.x0 - object.x1 > bridge || object.x0 - q.x1 > bridge) continue;
      double gap2 = kInf;
      for (std::size_t i : q.members) {
        for (std::size_t j : object.members) {
          const double dx = pts[i].x() - pts[j].x(), dy = pts[i].y() - pts[j].y();
          gap2 = std::min(gap2, dx * dx + dy * dy);
        }
      }
      if (gap2 > bridge2 || gap2 >= pick_gap2) continue;
      // The strip between them: x between the facing ends, y where both extend.
      const double sx0 = q.x0 > object.x1 ? object.x1 : q.x1, sx1 = q.x0 > object.x1 ? q.x0 : object.x0;
      const double sy0 = std::max(q.y0, object.y0), sy1 = std::min(q.y1, object.y1);
      if (sx1 > sx0 && sy1 > sy0) {
        std::size_t seen = 0;
        for (const Eigen::Vector2d& g : ground)
          seen += g.x() > sx0 && g.x() < sx1 && g.y() > sy0 && g.y() < sy1;
        if (static_cast<double>(seen) >= kGapGround * ground_density * (sx1 - sx0) * (sy1 - sy0)) continue;
      }
      pick = r;
      pick_gap2 = gap2;
    }
    if (pick_gap2 == kInf) break;
    joined[pick] = 1;
    const Piece& q = pieces[pick];
    if (shadows) {
      Shadow sh;
      sh.x0 = q.x0 > object.x1 ? object.x1 : q.x1;
      sh.x1 = q.x0 > object.x1 ? q.x0 : object.x0;
      sh.y0 = std::max(q.y0, object.y0);
      sh.y1 = std::min(q.y1, object.y1);
      const double area = (sh.x1 - sh.x0) * (sh.y1 - sh.y0);
      if (sh.x1 > sh.x0 && sh.y1 > sh.y0 && ground_density > 0) {
        auto inside = [&](double x, double y) { return x > sh.x0 && x < sh.x1 && y > sh.y0 && y < sh.y1; };
        std::size_t seen = 0;  // every return in it: the ground, and any cluster's points
        for (const Eigen::Vector2d& g : ground) seen += inside(g.x(), g.y());
        for (const Eigen::Vector3d& p : pts) seen += inside(p.x(), p.y());
        sh.empty = std::clamp(1 - static_cast<double>(seen) / (ground_density * area), 0.0, 1.0);
        shadows->push_back(sh);
      }
    }
    object.x0 = std::min(object.x0, q.x0);
    object.x1 = std::max(object.x1, q.x1);
    object.y0 = std::min(object.y0, q.y0);
    object.y1 = std::max(object.y1, q.y1);
    object.members.insert(object.members.end(), q.members.begin(), q.members.end());
    for (std::size_t i : q.members) in[i] = 1;
  }
}

double empty_area(const std::vector<Eigen::Vector2d>& points, double length, double width, double cell) {
  if (length <= 0 || width <= 0 || cell <= 0) return 0;
  const auto nu = static_cast<std::size_t>(std::max(1.0, std::floor(length / cell)));
  const auto nv = static_cast<std::size_t>(std::max(1.0, std::floor(width / cell)));
  const double du = length / static_cast<double>(nu), dv = width / static_cast<double>(nv);
  std::vector<char> held(nu * nv, 0);
  for (const Eigen::Vector2d& p : points) {
    if (p.x() < 0 || p.x() > length || p.y() < 0 || p.y() > width) continue;
    const std::size_t i = std::min(nu - 1, static_cast<std::size_t>(p.x() / du));
    const std::size_t j = std::min(nv - 1, static_cast<std::size_t>(p.y() / dv));
    held[i * nv + j] = 1;
  }
  std::size_t empty = 0;
  for (char h : held) empty += h == 0;
  return static_cast<double>(empty) * du * dv;
}

double shadow_area(const std::vector<Shadow>& shadows, const Eigen::Vector2d& u, const Eigen::Vector2d& v,
                   double u0, double u1, double v0, double v1, double step) {
  if (shadows.empty() || u1 <= u0 || v1 <= v0) return 0;
  const auto nu = static_cast<std::size_t>(std::ceil((u1 - u0) / step));
  const auto nv = static_cast<std::size_t>(std::ceil((v1 - v0) / step));
  const double du = (u1 - u0) / static_cast<double>(nu), dv = (v1 - v0) / static_cast<double>(nv);
  double sum = 0;
  for (std::size_t i = 0; i < nu; ++i) {
    for (std::size_t j = 0; j < nv; ++j) {
      // The cell's centre, back into the candidate frame.
      const Eigen::Vector2d p =
          (u0 + (static_cast<double>(i) + 0.5) * du) * u + (v0 + (static_cast<double>(j) + 0.5) * dv) * v;
      double empty = 0;
      for (const Shadow& s : shadows) {
        if (p.x() > s.x0 && p.x() < s.x1 && p.y() > s.y0 && p.y() < s.y1) empty = std::max(empty, s.empty);
      }
      sum += empty;
    }
  }
  return sum * du * dv;
}

double solid_density(const Candidate& c, const std::vector<Shadow>& shadows, const Params& fp,
                     const Eigen::Vector2d& u, const Eigen::Vector2d& v, double u0, double u1, double v0,
                     double v1, Features& f) {
  if (fp.fill_empty_cells) {
    std::vector<Eigen::Vector2d> uv;
    uv.reserve(c.points.size());
    for (const Eigen::Vector3d& p : c.points)
      uv.emplace_back(p.head<2>().dot(u) - u0, p.head<2>().dot(v) - v0);
    f.shadow_area = empty_area(uv, u1 - u0, v1 - v0, 2 * f.crop_spacing);
  } else {
    f.shadow_area = shadow_area(shadows, u, v, u0, u1, v0, v1);
  }
  if (!(fp.bridge_fill || fp.fill_empty_cells) || f.shadow_area <= 0) return f.density;
  const double rectangle = f.length_measured * f.width_measured;
  return f.density * rectangle / std::max(rectangle - f.shadow_area, 1e-6);
}

}  // namespace canopy::classify
