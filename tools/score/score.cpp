#include "score/score.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <stdexcept>

#include "canopy/common/error.h"
#include "canopy/common/stats.h"
#include "canopy/documents/detections.h"
#include "canopy/documents/scene_score.h"
#include "canopy/documents/scene_truth.h"
#include "canopy/formats/json_document.h"
#include "canopy/formats/provenance.h"
#include "score/clutter.h"
#include "score/intervals.h"

namespace canopy::score {
namespace {

using documents::ScoreMatch;
using documents::ScoreRow;
using documents::ScoreValue;
using Malformed = formats::MalformedField;

ScoreValue maybe(double v) { return std::isfinite(v) ? ScoreValue(v) : ScoreValue(); }

// Everything measured on one set of tiles.
struct Tally {
  int tiles = 0, candidates = 0, none = 0, detections = 0, truths = 0, tp = 0, identified = 0, flips = 0;
  double area = 0, cover_sum = 0;
  std::vector<double> position, heading;
  int class_detections = 0, class_tp = 0, class_identified = 0;
  std::vector<double> class_position, class_heading;
  // Both levels: found vehicles whose class (or model) the answer names, and the position and
  // axis (modulo 180) errors of every found vehicle.
  int any_class_right = 0;
  std::vector<double> any_position, any_heading;
};

}  // namespace

Truth parse_truth(const std::string& text_, const std::string& name) {
  const documents::SceneTruth doc = documents::read_scene_truth(text_, name);
  Truth t;
  t.name = name;
  try {
    if (!doc.extent) throw Malformed("truth: missing \"extent\"");
    t.extent_x = (*doc.extent)[0];
    t.extent_y = (*doc.extent)[1];
    for (std::size_t i = 0; i < doc.vehicles.size(); ++i) {
      const documents::TrueVehicle& x = doc.vehicles[i];
      const std::string w = "vehicles[" + std::to_string(i) + "]";
      if (x.model.empty()) throw Malformed(w + ": missing \"model\"");
      if (!x.pose) throw Malformed(w + ": missing \"pose\"");
      if (!x.pose->z) throw Malformed(w + ".pose: missing \"z\"");
      if (!x.pose->heading) throw Malformed(w + ".pose: missing \"heading\"");
      if (!x.canopy_cover) throw Malformed(w + ": missing \"canopy_cover\"");
      t.vehicles.push_back(TrueVehicle{static_cast<int>(x.instance), x.model, x.pose->x, x.pose->y,
                                       *x.pose->z, *x.pose->heading, *x.canopy_cover, x.cls, x.footprint});
    }
    for (const documents::TrueClutter& c : doc.clutter)
      t.clutter.push_back(TrueClutter{c.kind, c.x, c.y, c.length, c.width, c.heading});
  } catch (const Malformed& e) { throw common::DataError(name, e.what()); }
  return t;
}

Detections parse_detections(const std::string& text_, const std::string& name) {
  const documents::Detections doc = documents::read_detections(text_, name);
  Detections d;
  d.name = name;
  d.version = doc.version;
  try {
    if (!doc.candidates) throw Malformed("detections document: missing \"candidates\"");
    if (!doc.none) throw Malformed("detections document: missing \"none\"");
    d.candidates = *doc.candidates;
    d.none = *doc.none;
    for (std::size_t i = 0; i < doc.detections.size(); ++i) {
      const documents::Detection& x = doc.detections[i];
      const std::string w = "detections[" + std::to_string(i) + "]";
      if (x.level == "model" && x.model.empty())
        throw Malformed(w + ": a model-level detection without a model");
      if (!x.confidence) throw Malformed(w + ": missing \"confidence\"");
      if (!x.pose) throw Malformed(w + ": missing \"pose\"");
      const Detection e{x.candidate,   x.level,   x.model,   x.cls,     x.group,
                        *x.confidence, x.pose->x, x.pose->y, x.pose->z, x.pose->heading};
      (e.level == "model" ? d.detections : d.class_detections).push_back(e);
    }
    for (const documents::Rejection& r : doc.rejected) {
      if (r.position)
        d.rejected.push_back({r.candidate, r.reason.value_or(""), r.confidence, r.density, (*r.position)[0],
                              (*r.position)[1]});
    }
    const std::size_t found = d.detections.size() + d.class_detections.size();
    if (d.none + static_cast<int>(found) > d.candidates) {
      throw Malformed("detections (" + std::to_string(found) + ") + none (" + std::to_string(d.none) +
                      ") exceed the candidates (" + std::to_string(d.candidates) + ")");
    }
  } catch (const Malformed& e) { throw common::DataError(name, e.what()); }
  return d;
}

namespace {

// Greedy matching of `ds` (falling confidence, ties: candidate id) against the true vehicles
// not taken (taken[t] >= 0).
LevelMatch match_greedy(const std::vector<Detection>& ds, const Truth& truth, double radius,
                        const std::vector<int>& taken) {
  LevelMatch m;
  m.order.resize(ds.size());
  for (std::size_t i = 0; i < ds.size(); ++i) m.order[i] = static_cast<int>(i);
  std::sort(m.order.begin(), m.order.end(), [&](int a, int b) {
    if (ds[a].confidence != ds[b].confidence) return ds[a].confidence > ds[b].confidence;
    return ds[a].candidate < ds[b].candidate;
  });
  m.truth_of.assign(ds.size(), -1);
  m.detection_of.assign(truth.vehicles.size(), -1);
  for (int d : m.order) {
    int best = -1;
    double best_dist = radius;
    for (std::size_t t = 0; t < truth.vehicles.size(); ++t) {
      if (m.detection_of[t] >= 0 || (t < taken.size() && taken[t] >= 0)) continue;
      const double dist = std::hypot(ds[d].x - truth.vehicles[t].x, ds[d].y - truth.vehicles[t].y);
      if (dist > radius) continue;
      if (best < 0 || dist < best_dist ||
          (dist == best_dist && truth.vehicles[t].instance < truth.vehicles[best].instance)) {
        best = static_cast<int>(t);
        best_dist = dist;
      }
    }
    if (best >= 0) {
      m.truth_of[d] = best;
      m.detection_of[best] = d;
    }
  }
  return m;
}

}  // namespace

TileMatch match_tile(const Detections& det, const Truth& truth, double radius) {
  TileMatch m;
  static_cast<LevelMatch&>(m) = match_greedy(det.detections, truth, radius, {});
  m.cls = match_greedy(det.class_detections, truth, radius, m.detection_of);
  return m;
}

bool class_identified(const Detection& det, const TrueVehicle& tv) {
  for (const std::string* a : {&det.cls, &det.group}) {
    if (a->empty()) continue;
    if (*a == tv.model || (!tv.cls.empty() && *a == tv.cls)) return true;
  }
  return false;
}

double axis_error(double a, double b) {
  const double e = heading_error(a, b);
  return e > 90 ? 180 - e : e;
}

double heading_error(double a, double b) {
  double e = std::fmod(std::fabs(a - b), 360.0);
  return e > 180 ? 360 - e : e;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  return common::sorted_quantile(v, p / 100);
}

namespace {

// Everything measured on the tiles `which`.
Tally tally(const std::vector<Tile>& tiles, const std::vector<TileMatch>& matches,
            const std::vector<std::size_t>& which, const Params& params) {
  Tally s;
  for (std::size_t i : which) {
    const Tile& t = tiles[i];
    const TileMatch& m = matches[i];
    const LevelMatch& cm = m.cls;
    s.class_detections += static_cast<int>(t.detections.class_detections.size());
    for (std::size_t d = 0; d < cm.truth_of.size(); ++d) {
      if (cm.truth_of[d] < 0) continue;
      s.class_tp++;
      const Detection& det = t.detections.class_detections[d];
      const TrueVehicle& tv = t.truth.vehicles[cm.truth_of[d]];
      s.any_position.push_back(std::hypot(det.x - tv.x, det.y - tv.y));
      s.any_heading.push_back(axis_error(det.heading, tv.heading));
      if (!class_identified(det, tv)) continue;
      s.any_class_right++;
      s.class_identified++;
      s.class_position.push_back(std::hypot(det.x - tv.x, det.y - tv.y));
      s.class_heading.push_back(axis_error(det.heading, tv.heading));
    }
    s.tiles++;
    s.area += t.truth.extent_x * t.truth.extent_y / 1e4;
    s.candidates += t.detections.candidates;
    s.none += t.detections.none;
    s.detections += static_cast<int>(t.detections.detections.size());
    s.truths += static_cast<int>(t.truth.vehicles.size());
    for (const auto& v : t.truth.vehicles) s.cover_sum += v.cover;
    for (std::size_t d = 0; d < m.truth_of.size(); ++d) {
      if (m.truth_of[d] < 0) continue;
      s.tp++;
      const Detection& det = t.detections.detections[d];
      const TrueVehicle& tv = t.truth.vehicles[m.truth_of[d]];
      s.any_position.push_back(std::hypot(det.x - tv.x, det.y - tv.y));
      s.any_heading.push_back(axis_error(det.heading, tv.heading));
      if (det.model == tv.model || class_identified(det, tv)) s.any_class_right++;
      if (det.model != tv.model) continue;
      s.identified++;
      s.position.push_back(std::hypot(det.x - tv.x, det.y - tv.y));
      const double he = heading_error(det.heading, tv.heading);
      s.heading.push_back(he);
      if (he > params.flip_threshold) s.flips++;
    }
  }
  return s;
}

// One row of the summary table: the rates of a tally.
ScoreRow summary(const Tally& s, const ScoreValue& cover, const ScoreValue& noise) {
  const int fp = s.detections - s.tp, fn = s.truths - s.tp;
  const ScoreValue precision = ratio(s.tp, s.detections), recall = ratio(s.tp, s.truths);
  ScoreValue f1;
  if (precision.is_number() && recall.is_number()) {
    const double p = precision.number, r = recall.number;
    f1 = p + r > 0 ? 2 * p * r / (p + r) : 0.0;
  }
  return ScoreRow{{"cover", cover},
                  {"noise_mm", noise},
                  {"tiles", s.tiles},
                  {"area_ha", s.area},
                  {"true", s.truths},
                  {"candidates", s.candidates},
                  {"none", s.none},
                  {"detections", s.detections},
                  {"tp", s.tp},
                  {"fp", fp},
                  {"fn", fn},
                  {"precision", precision},
                  {"recall", recall},
                  {"f1", f1},
                  {"false_alarms_per_ha", ratio(fp, s.area)},
                  {"identified", s.identified},
                  {"identification", ratio(s.identified, s.tp)},
                  {"recognition", ratio(s.identified, s.truths)},
                  {"mean_vehicle_cover", ratio(s.cover_sum, s.truths)},
                  {"position_error_median_m", maybe(percentile(s.position, 50))},
                  {"position_error_p90_m", maybe(percentile(s.position, 90))},
                  {"heading_error_median_deg", maybe(percentile(s.heading, 50))},
                  {"heading_error_p90_deg", maybe(percentile(s.heading, 90))},
                  {"flips", s.flips},
                  {"class_detections", s.class_detections},
                  {"class_tp", s.class_tp},
                  {"class_fp", s.class_detections - s.class_tp},
                  {"class_identified", s.class_identified},
                  {"class_accuracy", ratio(s.class_identified, s.class_tp)},
                  {"class_position_error_median_m", maybe(percentile(s.class_position, 50))},
                  {"class_heading_error_median_deg", maybe(percentile(s.class_heading, 50))},
                  {"class_heading_error_p90_deg", maybe(percentile(s.class_heading, 90))},
                  {"found_any_level", s.tp + s.class_tp},
                  {"recall_any_level", ratio(s.tp + s.class_tp, s.truths)},
                  {"precision_any_level", ratio(s.tp + s.class_tp, s.detections + s.class_detections)},
                  {"false_alarms_any_level_per_ha", ratio(fp + s.class_detections - s.class_tp, s.area)},
                  {"class_right_any_level", s.any_class_right},
                  {"class_accuracy_any_level", ratio(s.any_class_right, s.tp + s.class_tp)},
                  {"position_error_any_level_median_m", maybe(percentile(s.any_position, 50))},
                  {"heading_axis_error_any_level_median_deg", maybe(percentile(s.any_heading, 50))},
                  {"heading_axis_error_any_level_p90_deg", maybe(percentile(s.any_heading, 90))}};
}

// The tiles' cover labels (first appearance) and noise levels (sorted).
struct Groups {
  std::vector<std::string> covers;
  std::vector<double> noises;
};

Groups groups(const std::vector<Tile>& tiles) {
  Groups g;
  for (const Tile& t : tiles) {
    if (!t.cover.empty() && std::find(g.covers.begin(), g.covers.end(), t.cover) == g.covers.end())
      g.covers.push_back(t.cover);
    if (std::isfinite(t.noise_mm) && std::find(g.noises.begin(), g.noises.end(), t.noise_mm) == g.noises.end()) {
      g.noises.push_back(t.noise_mm);
    }
  }
  std::sort(g.noises.begin(), g.noises.end());
  return g;
}

// The summary rows: all tiles, each cover label, each noise level, each label x noise.
std::vector<ScoreRow> summaries(const std::vector<Tile>& tiles, const std::vector<TileMatch>& matches,
                                const Params& params, const Groups& g) {
  auto select = [&](const std::string* cover, const double* noise) {
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < tiles.size(); ++i) {
      if (cover && tiles[i].cover != *cover) continue;
      if (noise && tiles[i].noise_mm != *noise) continue;
      which.push_back(i);
    }
    return which;
  };
  auto row = [&](const std::string* cover, const double* noise, const ScoreValue& c, const ScoreValue& n) {
    const std::vector<std::size_t> which = select(cover, noise);
    ScoreRow r = summary(tally(tiles, matches, which, params), c, n);
    const auto renders = renders_of(tiles, which);
    insert_after(r, "tiles", {{"renders", static_cast<int>(renders.size())}});
    insert_after(r, "true", {{"true_distinct", distinct_vehicles(tiles, renders)}});
    std::vector<Tally> per;
    for (const auto& members : renders) per.push_back(tally(tiles, matches, members, params));
    const double runs_per_render = renders.empty() ? 1 : static_cast<double>(which.size()) / renders.size();
    auto interval = [&](const char* key, RateKind kind, auto num, auto den) {
      std::vector<common::ClusterSum> sums;
      for (const Tally& t : per) sums.push_back({static_cast<double>(num(t)), static_cast<double>(den(t))});
      add_interval(r, key, sums, runs_per_render, kind);
    };
    const auto P = RateKind::proportion;
    interval(
        "precision", P, [](const Tally& t) { return t.tp; }, [](const Tally& t) { return t.detections; });
    interval(
        "recall", P, [](const Tally& t) { return t.tp; }, [](const Tally& t) { return t.truths; });
    interval(
        "false_alarms_per_ha", RateKind::per_area, [](const Tally& t) { return t.detections - t.tp; },
        [](const Tally& t) { return t.area; });
    interval(
        "identification", P, [](const Tally& t) { return t.identified; }, [](const Tally& t) { return t.tp; });
    interval(
        "recognition", P, [](const Tally& t) { return t.identified; }, [](const Tally& t) { return t.truths; });
    interval(
        "class_accuracy", P, [](const Tally& t) { return t.class_identified; },
        [](const Tally& t) { return t.class_tp; });
    interval(
        "recall_any_level", P, [](const Tally& t) { return t.tp + t.class_tp; },
        [](const Tally& t) { return t.truths; });
    interval(
        "precision_any_level", P, [](const Tally& t) { return t.tp + t.class_tp; },
        [](const Tally& t) { return t.detections + t.class_detections; });
    interval(
        "false_alarms_any_level_per_ha", RateKind::per_area,
        [](const Tally& t) { return t.detections - t.tp + t.class_detections - t.class_tp; },
        [](const Tally& t) { return t.area; });
    interval(
        "class_accuracy_any_level", P, [](const Tally& t) { return t.any_class_right; },
        [](const Tally& t) { return t.tp + t.class_tp; });
    return r;
  };
  std::vector<ScoreRow> rows;
  rows.push_back(row(nullptr, nullptr, "all", "all"));
  for (const auto& c : g.covers) rows.push_back(row(&c, nullptr, c, "all"));
  for (double n : g.noises) rows.push_back(row(nullptr, &n, "all", n));
  if (!g.covers.empty() && !g.noises.empty()) {
    for (const auto& c : g.covers) {
      for (double n : g.noises) rows.push_back(row(&c, &n, c, n));
    }
  }
  return rows;
}

// Precision-recall over the confidence (all tiles): one point per distinct confidence.
std::vector<ScoreRow> pr_curve(const std::vector<Tile>& tiles, const std::vector<TileMatch>& matches) {
  struct Ranked {
    double confidence;
    std::size_t tile;
    std::string candidate;
    bool tp;
  };
  std::vector<Ranked> ranked;
  int truths = 0;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    truths += static_cast<int>(tiles[i].truth.vehicles.size());
    const auto& ds = tiles[i].detections.detections;
    for (std::size_t d = 0; d < ds.size(); ++d) {
      ranked.push_back({ds[d].confidence, i, ds[d].candidate, matches[i].truth_of[d] >= 0});
    }
  }
  std::sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) {
    if (a.confidence != b.confidence) return a.confidence > b.confidence;
    if (a.tile != b.tile) return a.tile < b.tile;
    return a.candidate < b.candidate;
  });
  std::vector<ScoreRow> pr;
  int tp = 0;
  for (std::size_t k = 0; k < ranked.size(); ++k) {
    tp += ranked[k].tp ? 1 : 0;
    if (k + 1 < ranked.size() && ranked[k + 1].confidence == ranked[k].confidence) continue;
    const int n = static_cast<int>(k + 1);
    pr.push_back(ScoreRow{{"threshold", ranked[k].confidence},
                          {"detections", n},
                          {"tp", tp},
                          {"fp", n - tp},
                          {"precision", ratio(tp, n)},
                          {"recall", ratio(tp, truths)}});
  }
  return pr;
}

// Identification and recognition per true model, over all tiles and per cover label.
std::vector<ScoreRow> model_table(const std::vector<Tile>& tiles, const std::vector<TileMatch>& matches,
                                  const Groups& g) {
  std::vector<ScoreRow> models;
  std::vector<std::string> cover_groups{"all"};
  cover_groups.insert(cover_groups.end(), g.covers.begin(), g.covers.end());
  for (const auto& c : cover_groups) {
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < tiles.size(); ++i) {
      if (c == "all" || tiles[i].cover == c) which.push_back(i);
    }
    const auto renders = renders_of(tiles, which);
    // per model: true, matched, identified, true in distinct renders; and the same per render
    std::map<std::string, std::array<int, 4>> per;
    std::map<std::string, std::vector<std::array<int, 3>>> per_render;
    for (std::size_t r = 0; r < renders.size(); ++r) {
      for (std::size_t i : renders[r]) {
        for (std::size_t t = 0; t < tiles[i].truth.vehicles.size(); ++t) {
          const TrueVehicle& tv = tiles[i].truth.vehicles[t];
          auto& a = per[tv.model];
          auto& pr = per_render[tv.model];
          pr.resize(renders.size(), {0, 0, 0});
          a[0]++;
          pr[r][0]++;
          if (i == renders[r].front()) a[3]++;
          const int d = matches[i].detection_of[t];
          if (d < 0) continue;
          a[1]++;
          pr[r][1]++;
          if (tiles[i].detections.detections[d].model != tv.model) continue;
          a[2]++;
          pr[r][2]++;
        }
      }
    }
    for (const auto& [model, a] : per) {
      ScoreRow row{{"model", model},
                   {"cover", c},
                   {"true", a[0]},
                   {"true_distinct", a[3]},
                   {"matched", a[1]},
                   {"identified", a[2]},
                   {"recall", ratio(a[1], a[0])},
                   {"identification", ratio(a[2], a[1])},
                   {"recognition", ratio(a[2], a[0])}};
      // Renders without this model add nothing to either sum; they still count as draws.
      const auto& pr = per_render.at(model);
      auto sums = [&](int num, int den) {
        std::vector<common::ClusterSum> v;
        for (const auto& x : pr) v.push_back({static_cast<double>(x[num]), static_cast<double>(x[den])});
        return v;
      };
      const double runs_per_vehicle = a[3] > 0 ? static_cast<double>(a[0]) / a[3] : 1;
      add_interval(row, "recall", sums(1, 0), runs_per_vehicle, RateKind::proportion);
      add_interval(row, "identification", sums(2, 1), runs_per_vehicle, RateKind::proportion);
      add_interval(row, "recognition", sums(2, 0), runs_per_vehicle, RateKind::proportion);
      models.push_back(std::move(row));
    }
  }
  return models;
}

// One cover bin [lo, hi) ([lo, hi] for the last) over the tiles of noise level *n (all: null).
ScoreRow cover_bin(const std::vector<Tile>& tiles, const std::vector<TileMatch>& matches, const double* n,
                   double lo, double hi, bool last) {
  std::vector<std::size_t> which;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    if (!n || tiles[i].noise_mm == *n) which.push_back(i);
  }
  const auto renders = renders_of(tiles, which);
  int total = 0, detected = 0, recognised = 0, distinct = 0;
  std::vector<common::ClusterSum> recall_sums, recognition_sums;
  for (const auto& r : renders) {
    int r_total = 0, r_detected = 0, r_recognised = 0;
    for (std::size_t i : r) {
      for (std::size_t t = 0; t < tiles[i].truth.vehicles.size(); ++t) {
        const TrueVehicle& tv = tiles[i].truth.vehicles[t];
        if (tv.cover < lo || (last ? tv.cover > hi : tv.cover >= hi)) continue;
        r_total++;
        if (i == r.front()) distinct++;
        const int d = matches[i].detection_of[t];
        if (d < 0) continue;
        r_detected++;
        if (tiles[i].detections.detections[d].model == tv.model) r_recognised++;
      }
    }
    total += r_total;
    detected += r_detected;
    recognised += r_recognised;
    recall_sums.push_back({static_cast<double>(r_detected), static_cast<double>(r_total)});
    recognition_sums.push_back({static_cast<double>(r_recognised), static_cast<double>(r_total)});
  }
  ScoreRow row{{"cover_lo", lo},
               {"cover_hi", hi},
               {"noise_mm", n ? ScoreValue(*n) : ScoreValue("all")},
               {"true", total},
               {"true_distinct", distinct},
               {"detected", detected},
               {"recognised", recognised},
               {"recall", ratio(detected, total)},
               {"recognition", ratio(recognised, total)}};
  const double runs_per_vehicle = distinct > 0 ? static_cast<double>(total) / distinct : 1;
  add_interval(row, "recall", recall_sums, runs_per_vehicle, RateKind::proportion);
  add_interval(row, "recognition", recognition_sums, runs_per_vehicle, RateKind::proportion);
  return row;
}

// Recall and recognition against the measured per-vehicle canopy cover, overall and per noise.
std::vector<ScoreRow> cover_bins(const std::vector<Tile>& tiles, const std::vector<TileMatch>& matches,
                                 const Params& params, const Groups& g) {
  std::vector<ScoreRow> bins;
  const auto& edges = params.cover_bins;
  std::vector<const double*> noise_groups{nullptr};
  for (const double& n : g.noises) noise_groups.push_back(&n);
  for (const double* n : noise_groups) {
    for (std::size_t b = 0; b + 1 < edges.size(); ++b) {
      bins.push_back(cover_bin(tiles, matches, n, edges[b], edges[b + 1], b + 2 == edges.size()));
    }
  }
  return bins;
}

// A detection row's outcome: matched to `tv` (right or wrong, its distance and heading error),
// or a false alarm (tv null: the truth columns null).
void set_outcome(ScoreMatch& r, const Detection& det, const TrueVehicle* tv, bool right, double heading_err) {
  if (!tv) {
    r.outcome = "false_alarm";
    return;
  }
  r.outcome = right ? "right" : "wrong";
  r.instance = tv->instance;
  r.true_model = tv->model;
  r.cover = tv->cover;
  r.distance_m = std::hypot(det.x - tv->x, det.y - tv->y);
  r.heading_error_deg = heading_err;
}

// A detection's row before its outcome.
ScoreMatch detection_row(std::size_t tile, const Detection& det) {
  ScoreMatch r;
  r.tile = static_cast<std::int64_t>(tile);
  r.candidate = det.candidate;
  r.confidence = det.confidence;
  r.x = det.x;
  r.y = det.y;
  r.heading = det.heading;
  return r;
}

// One row per detection (by falling confidence) and per missed vehicle of tile i (the top-view
// pictures colour by outcome); returns the tile's true positives.
int outcome_rows(const Tile& t, const TileMatch& m, std::size_t i, double radius,
                 std::vector<ScoreMatch>& rows) {
  int tp_i = 0;
  for (int d : m.order) {
    const Detection& det = t.detections.detections[d];
    ScoreMatch r = detection_row(i, det);
    r.level = "model";
    r.model = det.model;
    if (!det.cls.empty()) r.cls = det.cls;
    if (m.truth_of[d] >= 0) {
      tp_i++;
      const TrueVehicle& tv = t.truth.vehicles[m.truth_of[d]];
      set_outcome(r, det, &tv, det.model == tv.model, heading_error(det.heading, tv.heading));
    } else {
      set_outcome(r, det, nullptr, false, 0);
    }
    rows.push_back(std::move(r));
  }
  // Class level: right when the group or class names the truth (class_identified); heading
  // error modulo 180.
  const LevelMatch& cm = m.cls;
  for (int d : cm.order) {
    const Detection& det = t.detections.class_detections[d];
    ScoreMatch r = detection_row(i, det);
    r.level = "class";
    r.cls = det.cls.empty() ? det.group : det.cls;
    if (cm.truth_of[d] >= 0) {
      tp_i++;
      const TrueVehicle& tv = t.truth.vehicles[cm.truth_of[d]];
      set_outcome(r, det, &tv, class_identified(det, tv), axis_error(det.heading, tv.heading));
    } else {
      set_outcome(r, det, nullptr, false, 0);
    }
    rows.push_back(std::move(r));
  }
  for (std::size_t v = 0; v < t.truth.vehicles.size(); ++v) {
    if (m.detection_of[v] >= 0 || cm.detection_of[v] >= 0) continue;
    const TrueVehicle& tv = t.truth.vehicles[v];
    ScoreMatch r;
    r.tile = static_cast<std::int64_t>(i);
    r.x = tv.x;
    r.y = tv.y;
    r.heading = tv.heading;
    r.outcome = "missed";
    r.instance = tv.instance;
    r.true_model = tv.model;
    r.cover = tv.cover;
    const MissedFate f = missed_fate(t, m, v, radius);
    r.fate = f.fate;
    if (!f.candidate.empty()) r.fate_candidate = f.candidate;
    if (!f.reason.empty()) r.fate_reason = f.reason;
    r.fate_density = f.density;
    rows.push_back(std::move(r));
  }
  return tp_i;
}

documents::ScoreTile tile_row(const Tile& t, int tp_i, const LevelMatch& cm) {
  const int n_class = static_cast<int>(t.detections.class_detections.size());
  int class_tp = 0;
  for (int x : cm.truth_of) class_tp += x >= 0 ? 1 : 0;
  tp_i -= class_tp;  // outcome_rows counted both levels
  const int n_det = static_cast<int>(t.detections.detections.size());
  const int n_true = static_cast<int>(t.truth.vehicles.size());
  documents::ScoreTile r;
  r.detections = t.detections.name;
  r.truth = t.truth.name;
  if (!t.cover.empty()) r.cover = t.cover;
  if (std::isfinite(t.noise_mm)) r.noise_mm = t.noise_mm;
  r.area_ha = t.truth.extent_x * t.truth.extent_y / 1e4;
  r.true_count = n_true;
  r.tp = tp_i;
  r.fp = n_det - tp_i;
  r.fn = n_true - tp_i;
  r.class_detections = n_class;
  r.class_tp = class_tp;
  r.class_fp = n_class - class_tp;
  r.fn_any_level = n_true - tp_i - class_tp;
  return r;
}

}  // namespace

documents::SceneScore score(const std::vector<Tile>& tiles, const Params& params) {
  std::vector<TileMatch> matches;
  for (const Tile& t : tiles) matches.push_back(match_tile(t.detections, t.truth, params.match_radius));
  const Groups g = groups(tiles);
  documents::SceneScore s;
  s.has_params = true;
  s.params.match_radius_m = params.match_radius;
  s.params.cover_bins = params.cover_bins;
  s.params.flip_threshold_deg = params.flip_threshold;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    s.tiles.push_back(tile_row(
        tiles[i], outcome_rows(tiles[i], matches[i], i, params.match_radius, s.matches), matches[i].cls));
  }
  s.summary = summaries(tiles, matches, params, g);
  s.pr = pr_curve(tiles, matches);
  s.models = model_table(tiles, matches, g);
  s.cover_bins = cover_bins(tiles, matches, params, g);
  s.reliability = reliability_table(tiles, s.matches, matches, params.match_radius);
  s.clutter = clutter_table(tiles, matches, params.match_radius);
  return s;
}

void validate(const Params& params) {
  if (!(params.match_radius > 0 && params.match_radius <= 100))
    throw common::UsageError("--match-radius must be in (0, 100m]");
  if (!(params.flip_threshold > 0 && params.flip_threshold <= 180))
    throw common::UsageError("--flip-threshold must be in (0, 180]");
  const auto& edges = params.cover_bins;
  if (edges.size() < 2) throw common::UsageError("--cover-bins needs at least two edges");
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (edges[i] < 0 || edges[i] > 1 || (i && edges[i] <= edges[i - 1])) {
      throw common::UsageError("--cover-bins: edges must rise strictly within [0, 1]");
    }
  }
}

}  // namespace canopy::score
