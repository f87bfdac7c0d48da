#include "report/density_section.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iterator>
#include <set>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/documents/candidates.h"
#include "canopy/documents/detections.h"
#include "canopy/documents/scene_truth.h"
#include "report/clutter_section.h"
#include "report/report.h"
#include "report/score_cells.h"

namespace canopy::report {

using documents::ScoreRow;

namespace {

bool exists(const std::string& p) {
  std::error_code ec;
  return std::filesystem::exists(p, ec);
}

std::string label(const ScoreRow& r) { return score_field(r, "cover").text; }

// The metrics of the ladder: key in score's summary, title, kind (rate with interval, number
// with interval, number).
struct Metric {
  const char* key;
  const char* title;
  enum Kind { rate, per_ha, degrees } kind;
};
const std::vector<Metric>& metrics() {
  static const std::vector<Metric> m = {
      {"recall_any_level", "recall (any level)", Metric::rate},
      {"precision_any_level", "precision (any level)", Metric::rate},
      {"class_accuracy_any_level", "class right (of found)", Metric::rate},
      {"identification", "model identified (of model answers)", Metric::rate},
      {"heading_axis_error_any_level_median_deg", "heading error, median (deg)", Metric::degrees},
      {"false_alarms_any_level_per_ha", "false alarms per ha", Metric::per_ha}};
  return m;
}

std::string show(const ScoreRow& r, const Metric& m) {
  if (m.kind == Metric::degrees) {
    const auto v = score_number(r, m.key);
    return v ? format_number("%.1f", *v) : "–";
  }
  return m.kind == Metric::rate ? score_ci(r, m.key, "%.1f%%", "%.1f", 100)
                                : score_ci(r, m.key, "%.1f", "%.1f", 1);
}

const ScoreRow* row_of(const DensityLevel& l, const std::string& cover) {
  return l.scored ? summary_row(l.score, cover) : nullptr;
}

// What an ablation's table says around its parameter file: the tool whose ablation it is, how the
// rungs were run again (up to the file) and what followed (after it, to the record that says why).
struct AblationText {
  const char* tool;
  const char* how;
  const char* then;
};
const AblationText kClassifyText{
    "classify", "the same candidates classified with ",
    ", collected and scored like canopy's; the file's header says which defaults it turns off, "
    "docs/decisions/classify.md why"};
const AblationText kDetectText{
    "detect", "the rung's whole chain run again — detect with ",
    ", then classify, the model chain where a candidate reaches it, collect and score like canopy's — "
    "on the class-level rungs; the file's header says which of detect's parameters it turns off, "
    "docs/decisions/density-ladder.md why"};

// A tool's `place`-th ablation (1: its first) beside canopy on a ladder's rungs where it has run (a
// changed default keeps its ablation in the report): found at either level per cover, class right,
// the wrong class and false alarms (all covers; score_cells.h class_ablation_table). `of`: the
// ablation on a rung (nullptr: none there); `ladder`: "the density ladder" or "the sensor ladder".
void ablation_table(std::ostringstream& md, const std::vector<DensityLevel>& rungs, const std::string& ladder,
                    const AblationText& text, int place,
                    const std::function<const DensityLevel::Ablation*(const DensityLevel&)>& of) {
  std::vector<std::pair<const DensityLevel*, const DensityLevel::Ablation*>> with;
  for (const DensityLevel& s : rungs)
    if (const DensityLevel::Ablation* a = of(s); s.scored && a && a->scored) with.emplace_back(&s, a);
  if (with.empty()) return;
  md << "\n**" << text.tool << "'s " << ablation_name(place) << " on " << ladder << "** (" << text.how << "`"
     << with.front().second->change << "`" << text.then
     << "): found at either level of each cover's vehicles, class right and the wrong class of the found "
        "and false alarms per ha (all covers), each with its count and 95% interval.\n\n";
  std::vector<AblationRung> table;
  for (const auto& [s, a] : with) table.push_back({format_number("%g", s->level), &s->score, &a->score});
  md << class_ablation_table("level", table);
}

// Every classify ablation's table on a ladder: the rungs' own, then each of their classify_more in
// order (as many as the rung with the most has).
void ablation_tables(std::ostringstream& md, const std::vector<DensityLevel>& rungs, const std::string& ladder) {
  ablation_table(md, rungs, ladder, kClassifyText, 1, [](const DensityLevel& s) { return &s.classify; });
  std::size_t more = 0;
  for (const DensityLevel& s : rungs) more = std::max(more, s.classify_more.size());
  for (std::size_t k = 0; k < more; ++k)
    ablation_table(md, rungs, ladder, kClassifyText, static_cast<int>(k) + 2, [k](const DensityLevel& s) {
      return k < s.classify_more.size() ? &s.classify_more[k] : nullptr;
    });
}

// The rows of a model-level comparison (verify's ablation, the model level's) for one rung: the
// model answers (identified of them), found at either level and class right (all covers), false
// alarms per ha; `c` canopy's summary row, `b` the ablation's.
void model_rows(std::ostringstream& md, const std::string& head, const ScoreRow* c, const ScoreRow* b) {
  md << head << "model answers, identified | " << rate_cell(c, "identification", "identified", "detections")
     << " | " << rate_cell(b, "identification", "identified", "detections") << " |\n";
  md << head << "found (all covers) | " << rate_cell(c, "recall_any_level", "found_any_level", "true")
     << " | " << rate_cell(b, "recall_any_level", "found_any_level", "true") << " |\n";
  md << head << "class right (all) | "
     << rate_cell(c, "class_accuracy_any_level", "class_right_any_level", "found_any_level") << " | "
     << rate_cell(b, "class_accuracy_any_level", "class_right_any_level", "found_any_level") << " |\n";
  md << head << "false alarms/ha (all) | " << false_alarm_cell(c) << " | " << false_alarm_cell(b) << " |\n";
}

// The model level's ablation on a ladder (the k-th entry of the rungs' detect list, a
// TILE_MODEL_DENSITY=<value>): the rung's whole chain again with the model level at that density,
// beside canopy on the rungs where it has run.
void model_level_table(std::ostringstream& md, const std::vector<DensityLevel>& rungs,
                       const std::string& ladder, std::size_t k) {
  std::vector<const DensityLevel*> with;
  for (const DensityLevel& s : rungs)
    if (s.scored && k < s.detect.size() && s.detect[k].scored) with.push_back(&s);
  if (with.empty()) return;
  const std::string& change = with.front()->detect[k].change;
  md << "\n**the model level's ablation on " << ladder << "** (the rung's whole chain run again with `"
     << change
     << "`, the points/m² of object from which a candidate also runs the model chain — canopy's is "
        "mk/scenes.mk's TILE_MODEL_DENSITY — on the class-level rungs, where candidates measure near either "
        "level; docs/decisions/density-scale.md why): model answers and identified of them, found at either "
        "level, class right of the found and false alarms per ha over all covers, each with its count and "
        "95% interval.\n\n";
  md << "| level | measure | canopy | ablation |\n|---|---|---|---|\n";
  for (const DensityLevel* l : with)
    model_rows(md, "| " + format_number("%g", l->level) + " | ", row_of(*l, "all"),
               summary_row(l->detect[k].score, "all"));
}

// Every detect ablation's table on a ladder, in their order: the k-th where it has run (the
// class-level rungs, mk/density.mk DENSITY_CLASS_MAX), the rung's whole chain again with another
// detect parameter file, so other candidates; the columns of classify's ablations. An entry that
// sets the model level instead has its own table (model_level_table); detect's are numbered
// among themselves.
void detect_ablation_tables(std::ostringstream& md, const std::vector<DensityLevel>& rungs,
                            const std::string& ladder) {
  std::size_t n = 0;
  for (const DensityLevel& s : rungs) n = std::max(n, s.detect.size());
  int place = 0;
  for (std::size_t k = 0; k < n; ++k) {
    bool model = false;
    for (const DensityLevel& s : rungs)
      if (k < s.detect.size()) model = model_level_entry(s.detect[k].change);
    if (model) {
      model_level_table(md, rungs, ladder, k);
      continue;
    }
    ablation_table(md, rungs, ladder, kDetectText, ++place,
                   [k](const DensityLevel& s) { return k < s.detect.size() ? &s.detect[k] : nullptr; });
  }
}

// verify's ablation beside canopy on the rungs of both ladders where it has run and either has a
// model-level answer (the option acts on the model chain only): the model answers (identified of
// them), found at either level and class right (all covers), false alarms per ha.
void verify_ablation_table(std::ostringstream& md, const std::vector<DensityLevel>& levels,
                           const std::vector<DensityLevel>& sensor) {
  std::vector<const DensityLevel*> with;
  const auto answers = [](const documents::SceneScore& s) {
    const ScoreRow* r = summary_row(s, "all");
    const auto d = r == nullptr ? std::nullopt : score_number(*r, "detections");
    return d.value_or(0);
  };
  for (const auto* ladder : {&levels, &sensor})
    for (const DensityLevel& l : *ladder)
      if (l.scored && l.verify.scored && (answers(l.score) > 0 || answers(l.verify.score) > 0))
        with.push_back(&l);
  if (with.empty()) return;
  md << "\n**verify's ablation on the density ladder** (the same model-level candidates verified again with `"
     << with.front()->verify.change
     << "` after verify's parameters, collected with the same class answers and scored like canopy's: "
        "docs/decisions/verify.md §17); the rungs where either has a model-level answer. Model answers: "
        "identified of the model-level answers; found at either level, class right of the found and false "
        "alarms per ha over all covers; each with its count and 95% interval.\n\n";
  md << "| ladder | level | measure | canopy | ablation |\n|---|---|---|---|---|\n";
  for (const DensityLevel* l : with) {
    const std::string head = "| " + (l->sensor.empty() ? std::string("pixel") : l->sensor) + " | " +
                             format_number("%g", l->level) + " | ";
    model_rows(md, head, row_of(*l, "all"), summary_row(l->verify.score, "all"));
  }
}

// A rung's ablation as the manifest names it, with its score when it has run.
DensityLevel::Ablation read_ablation(const documents::ManifestRungAblation& m) {
  DensityLevel::Ablation a{m.change, false, {}};
  if (!m.score.empty() && exists(m.score)) {
    a.score = documents::read_scene_score_file(m.score);
    a.scored = true;
  }
  return a;
}

}  // namespace

std::vector<DensityLevel> read_density_levels(const std::vector<documents::ManifestDensity>& levels) {
  std::vector<DensityLevel> out;
  for (const auto& m : levels) {
    DensityLevel l;
    l.level = m.level;
    l.spacing = m.spacing;
    l.sensor = m.sensor;
    l.score_path = m.score;
    l.classify = read_ablation(m.classify);
    l.verify = read_ablation(m.verify);
    for (const auto& a : m.classify_more) l.classify_more.push_back(read_ablation(a));
    for (const auto& a : m.detect) l.detect.push_back(read_ablation(a));
    if (exists(m.score)) {
      l.score = documents::read_scene_score_file(m.score);
      l.scored = true;
      const std::vector<SceneRun> runs = scene_runs(l.score);
      double all = 0, ground = 0;
      int n_all = 0, n_ground = 0;
      for (const SceneRun& r : runs) {
        const std::string index = r.dir + "/cands/index.json";
        if (!exists(index)) continue;
        const documents::Candidates c = documents::read_candidates_file(index);
        if (const auto a = c.density_all()) {
          all += *a;
          ++n_all;
        }
        if (c.density.is_object() && c.density.contains("ground") && c.density["ground"].is_number()) {
          ground += c.density["ground"].get<double>();
          ++n_ground;
        }
      }
      for (const SceneRun& r : runs) {
        const std::string det = r.dir + "/detections.json";
        if (!exists(det)) continue;
        const documents::Detections d = documents::read_detections_file(det);
        if (d.by_reason)
          for (const auto& [reason, n] : *d.by_reason) l.by_reason[reason] += n;
        if (d.found) l.by_reason["found"] += *d.found;
      }
      for (const documents::ScoreMatch& m : l.score.matches) {
        if (!m.true_model || m.outcome == "false_alarm") continue;
        auto& [found, all] = l.model_found[*m.true_model];
        ++all;
        if (m.outcome == "right" || m.outcome == "wrong") ++found;
        if (m.outcome == "missed") l.missed_by_fate[fate_label(m)]++;
      }
      if (!l.sensor.empty()) {
        // The tile's truth.json, beside its runs (<tile>/noise-<mm>/): each tile once.
        std::set<std::string> seen;
        double pulses = 0, returns = 0;
        int n = 0;
        for (const SceneRun& r : runs) {
          const std::string truth = std::filesystem::path(r.dir).parent_path().string() + "/truth.json";
          if (!seen.insert(truth).second || !exists(truth)) continue;
          const documents::SceneTruth t = documents::read_scene_truth_file(truth);
          if (!t.pulses_per_m2 || !t.returns_per_m2) continue;
          pulses += *t.pulses_per_m2;
          returns += *t.returns_per_m2;
          ++n;
        }
        if (n > 0) {
          l.pulses = pulses / n;
          l.returns = returns / n;
        }
      }
      l.density_runs = n_all;
      if (n_all > 0) l.density_all = all / n_all;
      if (n_ground > 0) l.density_ground = ground / n_ground;
      // canopy's stages (the verify ablations' runs, verdict-ablation.json, are not canopy's cost)
      for (const SceneStageTime& t : scene_times(runs))
        if (canopy_stage(t.stage)) l.cpu_seconds += t.cpu_seconds;
      for (const SceneRun& r : runs) l.area_ha += r.area_ha;
    }
    out.push_back(std::move(l));
  }
  return out;
}

std::vector<DensityTarget> density_targets(const std::vector<DensityLevel>& levels) {
  struct Rule {
    const char* capability;
    const char* target;
    const char* cover;
    const char* key;
    double bound;
    bool at_least;
  };
  const std::vector<Rule> rules = {
      {"vehicles detected, light cover", ">= 90%", "light", "recall_any_level", 0.90, true},
      {"vehicles detected, medium cover", ">= 75%", "medium", "recall_any_level", 0.75, true},
      {"class right, of the detected (all covers)", ">= 85%", "all", "class_accuracy_any_level", 0.85, true},
      {"heading error median (all covers)", "<= 5 deg", "all", "heading_axis_error_any_level_median_deg", 5,
       false},
      {"false alarms per ha (all covers)", "<= 1", "all", "false_alarms_any_level_per_ha", 1, false},
      {"model identification (all covers)", ">= 95%", "all", "identification", 0.95, true}};
  std::vector<DensityTarget> out;
  for (const Rule& r : rules) {
    DensityTarget t{r.capability, r.target, 0, 0};
    // From the top down: the lowest level above which every level meets the target.
    for (int pass = 0; pass < 2; ++pass) {
      double from = 0;
      for (auto it = levels.rbegin(); it != levels.rend(); ++it) {
        const ScoreRow* row = row_of(*it, r.cover);
        if (row == nullptr) break;
        // pass 1: the interval's conservative end (lo for "at least", hi for "at most"); a
        // median has no interval and is judged by itself.
        std::optional<double> v = score_number(*row, r.key);
        if (pass == 1) {
          const auto b = score_number(*row, std::string(r.key) + (r.at_least ? "_lo" : "_hi"));
          if (b) v = b;
        }
        if (!v || (r.at_least ? *v < r.bound : *v > r.bound)) break;
        from = it->level;
      }
      (pass == 0 ? t.from_level : t.from_level_bound) = from;
    }
    out.push_back(t);
  }
  return out;
}

std::string density_csv(const std::vector<DensityLevel>& levels, const std::string& part) {
  std::ostringstream csv;
  csv << "level,spacing_m,density_all,density_ground,cover,metric,value,lo,hi\n";
  auto opt = [](const std::optional<double>& v) { return v ? format_number("%.6g", *v) : std::string(); };
  for (const DensityLevel& l : levels) {
    if (!l.scored) continue;
    for (const ScoreRow* r : cover_rows(l.score)) {
      for (const Metric& m : metrics()) {
        if (part == "rates" && m.kind != Metric::rate) continue;
        if (part == "errors" && m.kind == Metric::rate) continue;
        csv << format_number("%g", l.level) << ',' << format_number("%g", l.spacing) << ','
            << (l.density_all > 0 ? format_number("%.1f", l.density_all) : "") << ','
            << (l.density_ground > 0 ? format_number("%.1f", l.density_ground) : "") << ',' << label(*r)
            << ',' << m.key << ',' << opt(score_number(*r, m.key)) << ','
            << opt(score_number(*r, std::string(m.key) + "_lo")) << ','
            << opt(score_number(*r, std::string(m.key) + "_hi")) << '\n';
      }
    }
  }
  return csv.str();
}

namespace {

// The level table: one row per cover of each level (the pixel ladder: its spacing; the sensor
// ladder: the measured pulses and returns per m²).
void level_table(std::ostringstream& md, const std::vector<DensityLevel>& levels, bool sensor) {
  md << (sensor ? "| level (pulses/m²) | measured pulses / returns (per m²) | "
                : "| level (pts/m²) | spacing (m) | ")
     << "measured all / open ground (pts/m²) | cover | tiles | vehicles | "
        "found (model + class) | recall | precision | class right | model identified | heading median (deg) "
        "| "
        "false alarms/ha | CPU s/ha |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const DensityLevel& l : levels) {
    const std::string second =
        sensor
            ? (l.pulses > 0 ? format_number("%.1f", l.pulses) + " / " + format_number("%.1f", l.returns) : "–")
            : format_number("%.3f", l.spacing);
    const std::string head = format_number("%g", l.level) + " | " + second + " | ";
    if (!l.scored) {
      md << "| " << head << "not run (no " << l.score_path << ") | | | | | | | | | | | |\n";
      continue;
    }
    const std::string dens = (l.density_all > 0 ? format_number("%.0f", l.density_all) : "–") + " / " +
                             (l.density_ground > 0 ? format_number("%.0f", l.density_ground) : "–");
    const std::string cpu = l.area_ha > 0 ? format_number("%.0f", l.cpu_seconds / l.area_ha) : "–";
    for (const ScoreRow* r : cover_rows(l.score)) {
      const bool all = label(*r) == "all";
      md << "| " << (all ? "**" + format_number("%g", l.level) + "**" : format_number("%g", l.level)) << " | "
         << second << " | " << dens << " | " << label(*r) << " | " << score_count(*r, "tiles") << " | "
         << score_count(*r, "true") << " | " << counts(*r, "found_any_level", "true") << " ("
         << counts(*r, "tp", "found_any_level") << " model) | ";
      for (std::size_t i = 0; i < metrics().size(); ++i) md << show(*r, metrics()[i]) << " | ";
      md << (all ? cpu : "") << " |\n";
    }
  }
}

// Per model and per reason, one column per level that ran; then where each capability begins.
void detail_tables(std::ostringstream& md, const std::vector<DensityLevel>& levels, const char* unit) {
  std::vector<const DensityLevel*> ran;
  std::set<std::string> models, reasons, fates;
  for (const DensityLevel& l : levels) {
    if (!l.scored) continue;
    ran.push_back(&l);
    for (const auto& [m, fa] : l.model_found) models.insert(m);
    for (const auto& [r, n] : l.by_reason) reasons.insert(r);
    for (const auto& [f, n] : l.missed_by_fate) fates.insert(f);
  }
  if (!ran.empty()) {
    // One row per key, one column per level that ran; cell(level, key) the entry's text, name(key)
    // the row's label.
    const auto as_is = [](const std::string& k) { return k; };
    auto table = [&](const char* first, const auto& keys, auto cell, auto name) {
      md << "| " << first << " |";
      for (const DensityLevel* l : ran) md << " " << format_number("%g", l->level) << " |";
      md << "\n|---|";
      for (std::size_t i = 0; i < ran.size(); ++i) md << "---|";
      md << "\n";
      for (const std::string& k : keys) {
        md << "| " << name(k) << " |";
        for (const DensityLevel* l : ran) md << " " << cell(*l, k) << " |";
        md << "\n";
      }
    };
    md << "\n**Found at either level, per model** (found / true, every cover level; the columns are the "
          "levels in "
       << unit << "):\n\n";
    table(
        "model", models,
        [](const DensityLevel& l, const std::string& m) {
          const auto it = l.model_found.find(m);
          return it == l.model_found.end()
                     ? std::string("–")
                     : std::to_string(it->second.first) + "/" + std::to_string(it->second.second);
        },
        as_is);
    md << "\n**What became of the candidates** (detections.json's reasons summed over the level's tiles; "
          "\"found\": answered as a vehicle):\n\n";
    table(
        "reason", reasons,
        [](const DensityLevel& l, const std::string& r) {
          const auto it = l.by_reason.find(r);
          return std::to_string(it == l.by_reason.end() ? 0 : it->second);
        },
        as_is);
    if (!fates.empty()) {
      md << "\n**Why the vehicles were missed** (vehicles found at neither level, by score's fate: the "
            "candidate nearest the vehicle within the match radius or its outline — none: no candidate; a "
            "rejection: refused, with its reason; a detection of another vehicle: taken; an unmatched "
            "detection: off centre; every cover level, each noise level's run counted):\n\n";
      table(
          "fate", fates,
          [](const DensityLevel& l, const std::string& f) {
            const auto it = l.missed_by_fate.find(f);
            return std::to_string(it == l.missed_by_fate.end() ? 0 : it->second);
          },
          as_is);
    }
    // score's clutter table, all covers: the kinds in the order score gives them (clutter kinds
    // by name, then the true vehicles and none), over every level that ran.
    std::vector<std::string> kinds;
    for (const DensityLevel* l : ran)
      for (const ScoreRow& r : l->score.clutter)
        if (label(r) == "all" &&
            std::find(kinds.begin(), kinds.end(), score_field(r, "kind").text) == kinds.end())
          kinds.push_back(score_field(r, "kind").text);
    const auto rank = [](const std::string& k) { return k == "none" ? 2 : k == "vehicle" ? 1 : 0; };
    std::stable_sort(kinds.begin(), kinds.end(),
                     [&](const std::string& a, const std::string& b) { return rank(a) < rank(b); });
    if (!kinds.empty()) {
      md << "\n**What the false alarms fell on** (score's clutter table, every cover level: a false alarm "
            "is put on the true vehicle whose footprint holds it — an answer on a part, a merge or a "
            "fragment beyond the match radius of its centre, or a second answer —, else on the clutter "
            "object whose box holds it or whose centre lies within the match radius, else on terrain or "
            "vegetation; model + class level):\n\n";
      table(
          "fell on", kinds,
          [&](const DensityLevel& l, const std::string& kind) {
            for (const ScoreRow& r : l.score.clutter)
              if (label(r) == "all" && score_field(r, "kind").text == kind)
                return score_text(score_field(r, "false_alarms"));
            return std::string("–");
          },
          [](const std::string& kind) { return kind + " (" + clutter_kind_mark(kind) + ")"; });
    }
  }
  md << "\n**Where each capability begins** (issue 27's targets): the lowest level from which the "
        "target is met at that level and every level above it — by the point estimate, and by the "
        "interval's conservative end (the lower bound of a rate that must be high, the upper bound of "
        "one that must be low; a median has no interval).\n\n";
  md << "| capability | target | met from (estimate) | met from (interval) |\n|---|---|---|---|\n";
  auto from = [&](double l) {
    return l > 0 ? format_number("%g", l) + " " + unit : std::string("at no level");
  };
  for (const DensityTarget& t : density_targets(levels))
    md << "| " << t.capability << " | " << t.target << " | " << from(t.from_level) << " | "
       << from(t.from_level_bound) << " |\n";
}

}  // namespace

std::string density_markdown(const std::vector<DensityLevel>& levels, const std::vector<std::string>& figures,
                             const std::vector<DensityLevel>& sensor) {
  std::ostringstream md;
  md << "\n## Density ladder\n\n"
     << "The scene experiment's tiles (its recipe, cover levels and models; noise 0) rendered at "
     << levels.size()
     << " densities: the same scenes at every level (the render's seed is the tile's place, not its "
        "spacing), only the pixel spacing changes (mk/density.mk; docs/decisions/density-ladder.md). "
        "Each level runs the unchanged tile workflow (detect's density rule, classify, the model chain "
        "where a candidate's object density reaches `TILE_MODEL_DENSITY`) and is scored like the scene "
        "experiment. \"Any level\": a model or a class answer. Rates: k/n and score's 95% interval "
        "(Wilson; every tile is its own render). Class right: the answer's class (a model answer: its "
        "model's, share/models/classes.csv) is the vehicle's. Heading: the axis error (modulo 180) of "
        "every found vehicle. CPU: every stage of the level (rendering included) per hectare of tile.\n\n";
  level_table(md, levels, false);
  detail_tables(md, levels, "pts/m²");
  ablation_tables(md, levels, "the density ladder");
  detect_ablation_tables(md, levels, "the density ladder");
  for (const std::string& f : figures) md << "\n![density ladder](" << f << ")\n";
  if (!figures.empty())
    md << "\n(One line per cover level; the levels at equal spacing; the bars are the 95% intervals, also in "
          "the table and in ladder.csv.)\n";
  verify_ablation_table(md, levels, sensor);
  if (sensor.empty()) return md.str();
  const std::string preset = sensor.front().sensor;
  md << "\n### The ladder on the realistic sensor (" << preset << ")\n\n"
     << "The same tiles (recipe, cover levels, models, seeds; noise 0) rendered in sensor mode with the "
        "preset `"
     << preset
     << "` (share/sensors/): pulses with a beam footprint, an oscillating mirror and multiple returns, "
        "the preset's flight lines along the recipe's two headings; each level's nominal pulses per m² set "
        "by the preset's pulse rate (× f) and speed (÷ f). Measured pulses and returns per m²: "
        "rangetrace's count over the level's tiles (truth.json). detect takes each point's direction "
        "toward the sensor from the flight's trajectory. Columns as above.\n\n";
  level_table(md, sensor, true);
  detail_tables(md, sensor, "pulses/m²");
  ablation_tables(md, sensor, "the sensor ladder");
  detect_ablation_tables(md, sensor, "the sensor ladder");
  // Side by side where both ladders have the nominal density.
  std::vector<std::pair<const DensityLevel*, const DensityLevel*>> both;
  for (const DensityLevel& s : sensor)
    for (const DensityLevel& p : levels)
      if (p.level == s.level && p.scored && s.scored) both.emplace_back(&p, &s);
  if (both.empty()) return md.str();
  md << "\n**Pixel spacing against the sensor at the same nominal density** (points/m² of the "
        "four image looks; pulses/m² of the sensor, whose returns are more): found at either level of the "
        "cover's vehicles, class right of the found (all covers), false alarms per ha (all covers), each "
        "with its count and 95% interval.\n\n";
  md << "| level | measure | pixel spacing | sensor (" << preset << ") |\n|---|---|---|---|\n";
  for (const auto& [p, s] : both) {
    const std::string lv = format_number("%g", p->level);
    auto line = [&](const char* what, const std::string& cover, const char* key, const char* k, const char* n) {
      md << "| " << lv << " | " << what << " | " << rate_cell(row_of(*p, cover), key, k, n) << " | "
         << rate_cell(row_of(*s, cover), key, k, n) << " |\n";
    };
    line("recall, light", "light", "recall_any_level", "found_any_level", "true");
    line("recall, medium", "medium", "recall_any_level", "found_any_level", "true");
    line("class right (all)", "all", "class_accuracy_any_level", "class_right_any_level", "found_any_level");
    md << "| " << lv << " | false alarms/ha (all) | " << false_alarm_cell(row_of(*p, "all")) << " | "
       << false_alarm_cell(row_of(*s, "all")) << " |\n";
  }
  return md.str();
}

}  // namespace canopy::report
