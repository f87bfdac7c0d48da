#include "score/clutter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include "canopy/common/math.h"
#include "score/intervals.h"

namespace canopy::score {
namespace {

using documents::ScoreRow;
using documents::ScoreValue;

// Counts of one kind in one render (over its runs).
struct KindSums {
  int false_alarms = 0, model_level = 0, class_level = 0, objects = 0, answered = 0;
};

}  // namespace

int clutter_at(const Truth& truth, double x, double y, double radius) {
  int best = -1;
  bool best_inside = false;
  double best_dist = 0;
  for (std::size_t k = 0; k < truth.clutter.size(); ++k) {
    const TrueClutter& c = truth.clutter[k];
    const double h = c.heading * common::kPi / 180;
    const double dx = x - c.x, dy = y - c.y;
    const double along = dx * std::cos(h) + dy * std::sin(h), across = -dx * std::sin(h) + dy * std::cos(h);
    const bool inside = std::abs(along) <= c.length / 2 && std::abs(across) <= c.width / 2;
    const double dist = std::hypot(dx, dy);
    if (!inside && dist > radius) continue;
    if (best < 0 || (inside && !best_inside) || (inside == best_inside && dist < best_dist)) {
      best = static_cast<int>(k);
      best_inside = inside;
      best_dist = dist;
    }
  }
  return best;
}

int vehicle_at(const Truth& truth, double x, double y) {
  int best = -1;
  double best_dist = 0;
  for (std::size_t k = 0; k < truth.vehicles.size(); ++k) {
    const TrueVehicle& v = truth.vehicles[k];
    const auto& f = v.footprint;
    if (f.size() < 3) continue;
    bool inside = false;  // crossing number: edges that straddle y, crossed right of x
    for (std::size_t i = 0, j = f.size() - 1; i < f.size(); j = i++) {
      if ((f[i][1] > y) != (f[j][1] > y) &&
          x < f[j][0] + (f[i][0] - f[j][0]) * (y - f[j][1]) / (f[i][1] - f[j][1]))
        inside = !inside;
    }
    if (!inside) continue;
    const double dist = std::hypot(x - v.x, y - v.y);
    if (best < 0 || dist < best_dist) {
      best = static_cast<int>(k);
      best_dist = dist;
    }
  }
  return best;
}

std::vector<ScoreRow> clutter_table(const std::vector<Tile>& tiles, const std::vector<TileMatch>& matches,
                                    double radius) {
  // Per tile: each clutter object's false alarms by level; the false alarms on no object.
  struct TileCounts {
    std::vector<std::array<int, 2>> per_object;   // model level, class level
    std::vector<std::array<int, 2>> per_vehicle;  // likewise, on the true vehicles
    std::array<int, 2> none{0, 0};
  };
  std::vector<TileCounts> counts(tiles.size());
  std::set<std::string> kinds;
  std::vector<std::string> covers{"all"};
  bool footprints = false;  // a "vehicle" row only where a truth outlines its vehicles
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const Truth& truth = tiles[i].truth;
    for (const auto& c : truth.clutter) kinds.insert(c.kind);
    if (!tiles[i].cover.empty() && std::find(covers.begin(), covers.end(), tiles[i].cover) == covers.end())
      covers.push_back(tiles[i].cover);
    for (const auto& v : truth.vehicles) footprints = footprints || !v.footprint.empty();
    counts[i].per_object.assign(truth.clutter.size(), {0, 0});
    counts[i].per_vehicle.assign(truth.vehicles.size(), {0, 0});
    auto put = [&](const std::vector<Detection>& ds, const LevelMatch& m, int level) {
      for (std::size_t d = 0; d < ds.size(); ++d) {
        if (m.truth_of[d] >= 0) continue;
        if (const int v = vehicle_at(truth, ds[d].x, ds[d].y); v >= 0) {
          counts[i].per_vehicle[v][level]++;
          continue;
        }
        const int k = clutter_at(truth, ds[d].x, ds[d].y, radius);
        (k >= 0 ? counts[i].per_object[k] : counts[i].none)[level]++;
      }
    };
    put(tiles[i].detections.detections, matches[i], 0);
    put(tiles[i].detections.class_detections, matches[i].cls, 1);
  }
  std::vector<std::string> rows_kinds(kinds.begin(), kinds.end());
  if (footprints) rows_kinds.push_back("vehicle");
  rows_kinds.push_back("none");
  std::vector<ScoreRow> rows;
  for (const std::string& cover : covers) {
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < tiles.size(); ++i) {
      if (cover == "all" || tiles[i].cover == cover) which.push_back(i);
    }
    const auto renders = renders_of(tiles, which);
    double area = 0;
    std::vector<double> render_area(renders.size(), 0);
    for (std::size_t r = 0; r < renders.size(); ++r) {
      for (std::size_t i : renders[r])
        render_area[r] += tiles[i].truth.extent_x * tiles[i].truth.extent_y / 1e4;
      area += render_area[r];
    }
    const double runs_per_render = renders.empty() ? 1 : static_cast<double>(which.size()) / renders.size();
    for (const std::string& kind : rows_kinds) {
      const bool none = kind == "none";
      std::vector<KindSums> per(renders.size());
      KindSums all;
      int distinct = 0;
      for (std::size_t r = 0; r < renders.size(); ++r) {
        for (std::size_t i : renders[r]) {
          const Truth& truth = tiles[i].truth;
          if (none) {
            per[r].model_level += counts[i].none[0];
            per[r].class_level += counts[i].none[1];
            continue;
          }
          // One object of the kind: its false alarms by level.
          auto object = [&](const std::array<int, 2>& n) {
            per[r].objects++;
            if (i == renders[r].front()) distinct++;
            per[r].model_level += n[0];
            per[r].class_level += n[1];
            per[r].answered += n[0] + n[1] > 0 ? 1 : 0;
          };
          if (kind == "vehicle") {
            for (std::size_t k = 0; k < truth.vehicles.size(); ++k)
              if (!truth.vehicles[k].footprint.empty()) object(counts[i].per_vehicle[k]);
            continue;
          }
          for (std::size_t k = 0; k < truth.clutter.size(); ++k)
            if (truth.clutter[k].kind == kind) object(counts[i].per_object[k]);
        }
        per[r].false_alarms = per[r].model_level + per[r].class_level;
        all.false_alarms += per[r].false_alarms;
        all.model_level += per[r].model_level;
        all.class_level += per[r].class_level;
        all.objects += per[r].objects;
        all.answered += per[r].answered;
      }
      auto or_null = [&](int v) { return none ? ScoreValue() : ScoreValue(v); };
      ScoreRow row{{"cover", cover},
                   {"kind", kind},
                   {"tiles", static_cast<int>(which.size())},
                   {"renders", static_cast<int>(renders.size())},
                   {"area_ha", area},
                   {"objects", or_null(all.objects)},
                   {"objects_distinct", or_null(distinct)},
                   {"false_alarms", all.false_alarms},
                   {"model_level", all.model_level},
                   {"class_level", all.class_level},
                   {"false_alarms_per_ha", ratio(all.false_alarms, area)},
                   {"answered", or_null(all.answered)},
                   {"answered_share", none ? ScoreValue() : ratio(all.answered, all.objects)}};
      std::vector<common::ClusterSum> fa, share;
      for (std::size_t r = 0; r < renders.size(); ++r) {
        fa.push_back({static_cast<double>(per[r].false_alarms), render_area[r]});
        share.push_back({static_cast<double>(per[r].answered), static_cast<double>(per[r].objects)});
      }
      add_interval(row, "false_alarms_per_ha", fa, runs_per_render, RateKind::per_area);
      add_interval(row, "answered_share", share,
                   distinct > 0 ? static_cast<double>(all.objects) / distinct : 1, RateKind::proportion);
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

}  // namespace canopy::score
