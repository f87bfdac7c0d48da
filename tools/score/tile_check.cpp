// score: a tile's detections and truth must be of one tile (score.h check_same_tile; stop 71).
#include <algorithm>
#include <limits>
#include <string>

#include "canopy/common/error.h"
#include "score/score.h"

namespace canopy::score {

void check_same_tile(const Tile& t) {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  int truths = 0;
  const auto grow = [&](double x, double y) {
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
    ++truths;
  };
  for (const TrueVehicle& v : t.truth.vehicles) grow(v.x, v.y);
  for (const TrueClutter& c : t.truth.clutter) grow(c.x, c.y);
  const double margin = std::max(t.truth.extent_x, t.truth.extent_y) + 10;
  const auto near = [&](double x, double y) {
    return x >= x0 - margin && x <= x1 + margin && y >= y0 - margin && y <= y1 + margin;
  };
  int positions = 0;
  for (const auto* ds : {&t.detections.detections, &t.detections.class_detections}) {
    for (const Detection& d : *ds) {
      if (near(d.x, d.y)) return;
      ++positions;
    }
  }
  for (const Rejection& r : t.detections.rejected) {
    if (near(r.x, r.y)) return;
    ++positions;
  }
  if (truths == 0 || positions == 0) return;
  throw common::DataError(
      t.detections.name, "none of its " + std::to_string(positions) +
                             " detections and rejected candidates lies within the extent of the truth " +
                             t.truth.name + " (" + std::to_string(truths) + " objects) plus " +
                             std::to_string(static_cast<int>(margin)) + " m: the detections of another tile?");
}

}  // namespace canopy::score
