// score: why a missed vehicle was missed (score.h missed_fate; formats/README.md "Scene score",
// stop 71).
#include <cmath>
#include <limits>

#include "score/score.h"

namespace canopy::score {

namespace {

// Whether (x, y) lies inside the polygon (even-odd rule; a point on an edge may fall either way).
bool inside(const std::vector<std::array<double, 2>>& poly, double x, double y) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0]) in = !in;
  }
  return in;
}

}  // namespace

MissedFate missed_fate(const Tile& t, const TileMatch& m, std::size_t v, double radius) {
  const TrueVehicle& tv = t.truth.vehicles[v];
  // The nearest reaching candidate so far: its distance, id and what it says.
  double best = std::numeric_limits<double>::infinity();
  MissedFate fate{"no_candidate", "", "", std::nullopt};
  const auto consider = [&](const std::string& id, double x, double y, const MissedFate& f) {
    const double dist = std::hypot(x - tv.x, y - tv.y);
    if (dist > radius && !(tv.footprint.size() >= 3 && inside(tv.footprint, x, y))) return;
    if (dist < best || (dist == best && id < fate.candidate)) {
      best = dist;
      fate = f;
    }
  };
  const auto detections = [&](const std::vector<Detection>& ds, const LevelMatch& lm) {
    for (std::size_t d = 0; d < ds.size(); ++d)
      consider(ds[d].candidate, ds[d].x, ds[d].y,
               {lm.truth_of[d] >= 0 ? "taken" : "off_centre", ds[d].candidate, "", std::nullopt});
  };
  detections(t.detections.detections, m);
  detections(t.detections.class_detections, m.cls);
  for (const Rejection& r : t.detections.rejected)
    consider(r.candidate, r.x, r.y, {"refused", r.candidate, r.reason, r.density});
  return fate;
}

}  // namespace canopy::score
