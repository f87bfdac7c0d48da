#include "score/intervals.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace canopy::score {
namespace {

using documents::ScoreMatch;
using documents::ScoreRow;
using documents::ScoreValue;

}  // namespace

ScoreValue ratio(double a, double b) { return b > 0 ? ScoreValue(a / b) : ScoreValue(); }

std::vector<std::vector<std::size_t>> renders_of(const std::vector<Tile>& tiles,
                                                 const std::vector<std::size_t>& which) {
  std::vector<std::vector<std::size_t>> renders;
  std::map<std::string, std::size_t> index;
  for (std::size_t i : which) {
    auto [it, fresh] = index.emplace(tiles[i].truth.name, renders.size());
    if (fresh) renders.emplace_back();
    renders[it->second].push_back(i);
  }
  return renders;
}

int distinct_vehicles(const std::vector<Tile>& tiles, const std::vector<std::vector<std::size_t>>& renders) {
  int n = 0;
  for (const auto& r : renders) n += static_cast<int>(tiles[r.front()].truth.vehicles.size());
  return n;
}

void insert_after(ScoreRow& row, const std::string& key,
                  std::initializer_list<std::pair<std::string, ScoreValue>> cells) {
  auto it = std::find_if(row.begin(), row.end(), [&](const auto& c) { return c.first == key; });
  if (it == row.end()) throw std::logic_error("score: no column " + key);
  row.insert(it + 1, cells.begin(), cells.end());
}

void add_interval(ScoreRow& row, const std::string& key, const std::vector<common::ClusterSum>& per_render,
                  double runs_per_render, RateKind kind) {
  double num = 0, den = 0;
  for (const auto& c : per_render) {
    num += c.num;
    den += c.den;
  }
  if (!(den > 0)) {
    insert_after(row, key, {{key + "_lo", nullptr}, {key + "_hi", nullptr}});
    return;
  }
  const double f = runs_per_render > 0 ? 1 / runs_per_render : 1;
  common::Interval ci;
  if (kind == RateKind::proportion) {
    ci = common::wilson_effective(std::min(1.0, num / den), den * f);
  } else {
    const common::Interval k = common::poisson_exact(static_cast<int>(std::lround(num * f)));
    ci = {k.lo / (den * f), k.hi / (den * f)};
  }
  if (const auto b = common::cluster_bootstrap(per_render)) {
    ci.lo = std::min(ci.lo, b->lo);
    ci.hi = std::max(ci.hi, b->hi);
  }
  insert_after(row, key, {{key + "_lo", ci.lo}, {key + "_hi", ci.hi}});
}

std::vector<ScoreRow> reliability_table(const std::vector<Tile>& tiles, const std::vector<ScoreMatch>& matches,
                                        const std::vector<TileMatch>& pairing, double radius) {
  std::vector<std::size_t> all(tiles.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  const auto renders = renders_of(tiles, all);
  std::vector<std::size_t> render_of(tiles.size());
  for (std::size_t r = 0; r < renders.size(); ++r) {
    for (std::size_t i : renders[r]) render_of[i] = r;
  }
  const double runs_per_render = renders.empty() ? 1 : static_cast<double>(tiles.size()) / renders.size();
  // Every answer: level, confidence, right, tile.
  struct Answer {
    std::string level;
    double confidence;
    bool right;
    std::size_t tile;
  };
  std::vector<Answer> answers;
  for (const ScoreMatch& m : matches) {
    if (m.outcome == "missed" || !m.confidence) continue;
    answers.push_back(
        {m.level.value_or("model"), *m.confidence, m.outcome == "right", static_cast<std::size_t>(m.tile)});
  }
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const auto& vehicles = tiles[i].truth.vehicles;
    for (const Rejection& r : tiles[i].detections.rejected) {
      if (!r.confidence) continue;  // a rejection that states no confidence is not judged
      bool costs = false;
      for (std::size_t t = 0; t < vehicles.size(); ++t) {
        const bool missed = pairing[i].detection_of[t] < 0 && pairing[i].cls.detection_of[t] < 0;
        if (missed && std::hypot(vehicles[t].x - r.x, vehicles[t].y - r.y) <= radius) costs = true;
      }
      answers.push_back({"none", *r.confidence, !costs, i});
    }
  }
  std::vector<ScoreRow> rows;
  for (const char* level : {"model", "class", "none"}) {
    for (int b = 0; b < 10; ++b) {
      const double lo = b / 10.0, hi = (b + 1) / 10.0;
      std::vector<common::ClusterSum> per(renders.size());
      int n = 0, right = 0;
      double conf_sum = 0;
      for (const Answer& a : answers) {
        if (a.level != level) continue;
        if (a.confidence < lo || (b == 9 ? a.confidence > hi : a.confidence >= hi)) continue;
        ++n;
        right += a.right;
        conf_sum += a.confidence;
        auto& x = per[render_of[a.tile]];
        x.num += a.right;
        x.den += 1;
      }
      ScoreRow row{{"level", level},         {"confidence_lo", lo}, {"confidence_hi", hi},
                   {"answers", n},           {"right", right},      {"mean_confidence", ratio(conf_sum, n)},
                   {"rate", ratio(right, n)}};
      add_interval(row, "rate", per, runs_per_render, RateKind::proportion);
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

}  // namespace canopy::score
