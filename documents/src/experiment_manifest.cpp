#include "canopy/documents/experiment_manifest.h"

#include <algorithm>
#include <iomanip>
#include <cstdlib>
#include <set>
#include <sstream>
#include <tuple>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/units.h"
#include "canopy/formats/text_lines.h"

namespace canopy::documents {

namespace {

using Key = std::tuple<std::string, std::string, int>;

struct Parser {
  const std::string& name;
  ExperimentManifest m;
  std::set<Key> trials;
  std::map<std::string, std::set<Key>> ablation_trials;
  std::set<std::string> real_names;
  int line = 0;

  [[noreturn]] void fail(const std::string& why) const {
    throw common::DataError(name, "line " + std::to_string(line) + ": " + why);
  }

  const std::string& word(const std::string& w, const char* what) const {
    const bool ok = !w.empty() && std::all_of(w.begin(), w.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
             c == '_' || c == '.';
    });
    if (!ok) fail(std::string(what) + " '" + w + "' is not a word of letters, digits, '-', '_' and '.'");
    return w;
  }

  int noise(const std::string& w) const {
    const bool digits = !w.empty() && w.size() <= 7 &&
                        std::all_of(w.begin(), w.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!digits || std::stoi(w) > 1000000)
      fail("noise '" + w + "' is not a whole number of millimetres (0 to 1000000)");
    return std::stoi(w);
  }

  // A decimal number (common::decimal_prefix's grammar, as parse_decimal reads options) in
  // (0, 1e6].
  double positive(const std::string& w, const char* what) const {
    const bool decimal =
        !w.empty() && common::decimal_prefix(w) == w.size() && common::decimal_problem(w).empty();
    const double v = decimal ? std::strtod(w.c_str(), nullptr) : 0;
    if (!(v > 0 && v <= 1e6)) fail(std::string(what) + " '" + w + "' is not a number in (0, 1000000]");
    return v;
  }

  void expect(const std::vector<std::string>& w, std::size_t lo, std::size_t hi, const char* form) const {
    if (w.size() < lo || w.size() > hi) fail(std::string("expected '") + form + "'");
  }

  static void remember(std::vector<std::string>& order, const std::string& x) {
    if (std::find(order.begin(), order.end(), x) == order.end()) order.push_back(x);
  }

  // The rung a density-verify, density-classify or density-detect record `w` (KIND LADDER LEVEL ...) follows:
  // the last record of its ladder (`pixel`: density; a preset: density-sensor), at its level.
  ManifestDensity& rung_of(const std::vector<std::string>& w) {
    const std::string ladder = word(w[1], "ladder");
    std::vector<ManifestDensity>& rungs = ladder == "pixel" ? m.density : m.density_sensor;
    const double level = positive(w[2], "density level");
    if (rungs.empty() || rungs.back().level != level || (ladder != "pixel" && rungs.back().sensor != ladder))
      fail(w[0] + " " + ladder + " " + w[2] + " does not follow its rung's record");
    return rungs.back();
  }

  // A density or density-sensor record's optional classify ablation (its words 4 and 5).
  static ManifestRungAblation classify_ablation(const std::vector<std::string>& w) {
    return w.size() == 6 ? ManifestRungAblation{w[4], w[5]} : ManifestRungAblation{};
  }

  ManifestTrial trial(const std::vector<std::string>& w, std::size_t at) const {
    return {word(w[at], "object"), word(w[at + 1], "scene"), noise(w[at + 2]), w[at + 3]};
  }

  void record(const std::vector<std::string>& w) {
    const std::string& kind = w[0];
    if (kind == "trial") {
      expect(w, 5, 5, "trial OBJECT SCENE NOISE_MM DIR");
      ManifestTrial t = trial(w, 1);
      if (!trials.insert({t.object, t.scene, t.noise_mm}).second)
        fail("a second trial " + w[1] + " " + w[2] + " " + w[3]);
      remember(m.objects, t.object);
      remember(m.scenes, t.scene);
      if (std::find(m.noises.begin(), m.noises.end(), t.noise_mm) == m.noises.end())
        m.noises.push_back(t.noise_mm);
      m.trials.push_back(std::move(t));
    } else if (kind == "model") {
      expect(w, 3, 3, "model OBJECT GRAPH");
      if (!m.models.emplace(word(w[1], "object"), w[2]).second) fail("a second model " + w[1]);
    } else if (kind == "render") {
      expect(w, 4, 4, "render OBJECT SCENE SCAN");
      const std::string key = word(w[1], "object") + "/" + word(w[2], "scene");
      if (!m.renders.emplace(key, w[3]).second) fail("a second render " + w[1] + " " + w[2]);
    } else if (kind == "ablation") {
      expect(w, 3, 3, "ablation NAME CHANGE");
      if (ablation_trials.count(word(w[1], "ablation"))) fail("a second ablation " + w[1]);
      ablation_trials[w[1]];
      std::string change = w[2];
      std::replace(change.begin(), change.end(), '+', ' ');
      m.ablations.push_back({w[1], change, {}});
    } else if (kind == "ablation-trial") {
      expect(w, 6, 6, "ablation-trial NAME OBJECT SCENE NOISE_MM MATCH");
      const auto a = std::find_if(m.ablations.begin(), m.ablations.end(),
                                  [&](const ManifestAblation& x) { return x.name == w[1]; });
      if (a == m.ablations.end()) fail("ablation '" + w[1] + "' is not declared before its trials");
      ManifestTrial t = trial(w, 2);
      if (!ablation_trials[w[1]].insert({t.object, t.scene, t.noise_mm}).second) {
        fail("a second trial " + w[2] + " " + w[3] + " " + w[4] + " of ablation " + w[1]);
      }
      a->trials.push_back(std::move(t));
    } else if (kind == "figure") {
      expect(w, 2, 2, "figure PATH");
      m.figures.push_back(w[1]);
    } else if (kind == "real") {
      expect(w, 3, 4, "real NAME DIR [TRUTH]");
      if (!real_names.insert(word(w[1], "real tile")).second) fail("a second real tile " + w[1]);
      m.real.push_back({w[1], w[2], w.size() == 4 ? w[3] : ""});
    } else if (kind == "real-ablation") {
      expect(w, 4, 4, "real-ablation NAME DIR CONFIG");
      if (m.real.empty() || m.real.back().name != w[1])
        fail("real-ablation " + w[1] + " does not follow its tile's real record");
      for (const ManifestRealAblation& a : m.real.back().ablations)
        if (a.dir == w[2] || a.config == w[3])
          fail("a second real-ablation " + w[1] + " with " + a.dir + " " + a.config);
      m.real.back().ablations.push_back({w[2], w[3]});
    } else if (kind == "density-verify") {
      expect(w, 5, 5, "density-verify LADDER LEVEL CHANGE SCORE");
      ManifestDensity& rung = rung_of(w);
      if (!rung.verify.score.empty()) fail("a second density-verify " + w[1] + " " + w[2]);
      std::string change = w[3];
      std::replace(change.begin(), change.end(), '+', ' ');
      rung.verify = {change, w[4]};
    } else if (kind == "density-classify" || kind == "density-detect") {
      const bool classify = kind == "density-classify";
      expect(w, 5, 5,
             classify ? "density-classify LADDER LEVEL CONFIG SCORE"
                      : "density-detect LADDER LEVEL CONFIG SCORE");
      ManifestDensity& rung = rung_of(w);
      std::vector<ManifestRungAblation>& list = classify ? rung.classify_more : rung.detect;
      // As many as the rung ran (mk/density.mk's lists), but each score once: a repeated one is
      // the same record written twice, not another ablation.
      for (const ManifestRungAblation& a : list)
        if (a.score == w[4]) fail(kind + " " + w[1] + " " + w[2] + ": " + w[4] + " a second time");
      list.push_back({w[3], w[4]});
    } else if (kind == "density") {
      expect(w, 4, 6, "density LEVEL SPACING SCORE [ABLATION_CONFIG ABLATION_SCORE]");
      if (w.size() == 5) fail("density: an ablation needs its parameter file and its score.json");
      const double level = positive(w[1], "density level"), spacing = positive(w[2], "pixel spacing");
      if (!m.density.empty() && level <= m.density.back().level)
        fail("density level " + w[1] + " does not rise above the one before it");
      m.density.push_back({level, spacing, w[3], "", classify_ablation(w)});
    } else if (kind == "density-sensor") {
      expect(w, 4, 6, "density-sensor LEVEL PRESET SCORE [ABLATION_CONFIG ABLATION_SCORE]");
      if (w.size() == 5) fail("density-sensor: an ablation needs its parameter file and its score.json");
      const double level = positive(w[1], "density level");
      const std::string preset = word(w[2], "sensor preset");
      if (!m.density_sensor.empty() && level <= m.density_sensor.back().level)
        fail("density-sensor level " + w[1] + " does not rise above the one before it");
      if (!m.density_sensor.empty() && preset != m.density_sensor.back().sensor)
        fail("density-sensor preset " + preset + " is not the one before it (" +
             m.density_sensor.back().sensor + "): one sensor ladder");
      m.density_sensor.push_back({level, 0, w[3], preset, classify_ablation(w)});
    } else {
      fail("unknown record '" + kind +
           "' (trial, model, render, ablation, ablation-trial, figure, real, real-ablation, density, "
           "density-sensor, density-verify, density-classify, density-detect)");
    }
  }

  // Every (object, scene, noise) of the grid, as a trial and in each ablation.
  void check_grid() const {
    if (m.trials.empty()) throw common::DataError(name, "lists no trial");
    const std::size_t grid = m.objects.size() * m.scenes.size() * m.noises.size();
    const auto missing = [&](const std::set<Key>& have) -> std::string {
      for (const auto& o : m.objects)
        for (const auto& s : m.scenes)
          for (int n : m.noises)
            if (!have.count({o, s, n})) return o + " " + s + " " + std::to_string(n);
      return "";
    };
    if (m.trials.size() != grid) {
      throw common::DataError(
          name,
          "the trials are not a full grid of their objects, scenes and noises: no trial " + missing(trials));
    }
    for (const auto& a : m.ablations) {
      const std::set<Key>& have = ablation_trials.at(a.name);
      for (const Key& k : have) {
        if (!trials.count(k)) {
          throw common::DataError(name, "ablation " + a.name + " has a trial " + std::get<0>(k) + " " +
                                            std::get<1>(k) + " " + std::to_string(std::get<2>(k)) +
                                            " that is not a trial");
        }
      }
      if (have.size() != grid)
        throw common::DataError(name, "ablation " + a.name + " has no trial " + missing(have));
    }
  }
};

}  // namespace

std::string ExperimentManifest::trial_dir(const std::string& object, const std::string& scene,
                                          int noise_mm) const {
  for (const auto& t : trials) {
    if (t.object == object && t.scene == scene && t.noise_mm == noise_mm) return t.path;
  }
  return "";
}

ExperimentManifest parse_experiment_manifest(const std::string& text, const std::string& name) {
  Parser p{name, {}, {}, {}, {}, 0};
  const std::vector<formats::TextLine> lines = formats::text_lines(text);
  if (lines.size() > kMaxManifestRecords) {
    throw common::DataError(name, "more than " + std::to_string(kMaxManifestRecords) + " records");
  }
  for (const formats::TextLine& l : lines) {
    p.line = l.number;
    p.record(l.words);
  }
  p.check_grid();
  return std::move(p.m);
}

ExperimentManifest read_experiment_manifest(const std::string& path) {
  return parse_experiment_manifest(common::read_file(path), path);
}

std::string write_experiment_manifest(const ExperimentManifest& m) {
  std::ostringstream out;
  for (const auto& t : m.trials)
    out << "trial " << t.object << ' ' << t.scene << ' ' << t.noise_mm << ' ' << t.path << '\n';
  for (const auto& [object, graph] : m.models) out << "model " << object << ' ' << graph << '\n';
  for (const auto& [key, scan] : m.renders) {
    const auto slash = key.find('/');
    out << "render " << key.substr(0, slash) << ' ' << key.substr(slash + 1) << ' ' << scan << '\n';
  }
  for (const auto& a : m.ablations) {
    std::string change = a.change;
    std::replace(change.begin(), change.end(), ' ', '+');
    out << "ablation " << a.name << ' ' << change << '\n';
    for (const auto& t : a.trials) {
      out << "ablation-trial " << a.name << ' ' << t.object << ' ' << t.scene << ' ' << t.noise_mm << ' '
          << t.path << '\n';
    }
  }
  for (const auto& f : m.figures) out << "figure " << f << '\n';
  for (const auto& r : m.real) {
    out << "real " << r.name << ' ' << r.dir << (r.truth.empty() ? "" : " " + r.truth) << '\n';
    for (const ManifestRealAblation& a : r.ablations)
      out << "real-ablation " << r.name << ' ' << a.dir << ' ' << a.config << '\n';
  }
  const auto verify = [&out](const std::string& ladder, const ManifestDensity& d) {
    if (d.verify.score.empty()) return;
    std::string change = d.verify.change;
    std::replace(change.begin(), change.end(), ' ', '+');
    out << "density-verify " << ladder << ' ' << d.level << ' ' << change << ' ' << d.verify.score << '\n';
  };
  const auto rung_ablations = [&out](const std::string& ladder, const ManifestDensity& d) {
    for (const ManifestRungAblation& a : d.classify_more)
      out << "density-classify " << ladder << ' ' << d.level << ' ' << a.change << ' ' << a.score << '\n';
    for (const ManifestRungAblation& a : d.detect)
      out << "density-detect " << ladder << ' ' << d.level << ' ' << a.change << ' ' << a.score << '\n';
  };
  out << std::setprecision(10);
  for (const auto& d : m.density) {
    out << "density " << d.level << ' ' << d.spacing << ' ' << d.score
        << (d.classify.score.empty() ? "" : " " + d.classify.change + " " + d.classify.score) << '\n';
    verify("pixel", d);
    rung_ablations("pixel", d);
  }
  for (const auto& d : m.density_sensor) {
    out << "density-sensor " << d.level << ' ' << d.sensor << ' ' << d.score
        << (d.classify.score.empty() ? "" : " " + d.classify.change + " " + d.classify.score) << '\n';
    verify(d.sensor, d);
    rung_ablations(d.sensor, d);
  }
  return out.str();
}

}  // namespace canopy::documents
