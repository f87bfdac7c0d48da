// classify's object: gap bridging (classify.md §21, --bridge), joining the clusters that a
// vehicle's own no-return gaps (windscreen, rear window) split off it.
#include <algorithm>
#include <limits>
#include <unordered_map>

#include "classify/features.h"

namespace canopy::classify {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

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
// `bridge_length` long. Nearest cluster first, until none joins.
void bridge_gaps(const std::vector<Eigen::Vector3d>& pts, const std::vector<std::size_t>& label,
                 std::size_t best, const std::vector<Eigen::Vector2d>& ground, double ground_density,
                 double link, double bridge, double bridge_length, std::vector<char>& in) {
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
      if (!within || !level || !short_enough) continue;
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
    object.x0 = std::min(object.x0, q.x0);
    object.x1 = std::max(object.x1, q.x1);
    object.y0 = std::min(object.y0, q.y0);
    object.y1 = std::max(object.y1, q.y1);
    object.members.insert(object.members.end(), q.members.begin(), q.members.end());
    for (std::size_t i : q.members) in[i] = 1;
  }
}

}  // namespace canopy::classify
