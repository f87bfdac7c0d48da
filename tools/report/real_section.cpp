// The report's "Real tiles" section: the tile workflow's documents of each real tile (detections,
// candidates index, truth and score through documents/), and
// the hand labels; every rate with its count and a 95% interval
// (common/stats.h: Wilson for proportions, exact Poisson for a count per area).
#include "report/real_section.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <set>
#include <sstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/stats.h"
#include "canopy/documents/candidates.h"
#include "canopy/documents/detections.h"
#include "canopy/documents/scene_score.h"
#include "canopy/documents/scene_truth.h"
#include "canopy/formats/csv_table.h"
#include "canopy/formats/json_document.h"
#include "report/report.h"
#include "report/score_cells.h"

namespace canopy::report {
namespace {

namespace fs = std::filesystem;
using formats::format_number;
using formats::MalformedField;

bool exists(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

// The detections document: counts, levels, classes, reasons, warning; the group of each
// detection by candidate id (for the class accuracy).
void read_detections(const std::string& path, RealTile& t, std::map<std::string, std::string>& group) {
  const documents::Detections d = documents::read_detections_file(path);
  try {
    auto need = [](const auto& v, const char* key) {
      if (!v) throw MalformedField(std::string("missing \"") + key + "\"");
      return *v;
    };
    t.version = d.version;
    t.candidates = need(d.candidates, "candidates");
    t.found = need(d.found, "found");
    const auto& dets = d.detections;
    for (const documents::Detection& e : dets) {
      const std::string& what = e.level == "class" ? e.cls : e.model;
      t.by_level[e.level]++;
      t.by_class[e.level + ": " + (what.empty() ? "?" : what)]++;
      group[e.candidate] = e.group;
    }
    if (t.version >= 2) {
      need(d.by_level, "by_level");
      for (const auto& [reason, n] : need(d.by_reason, "by_reason")) t.by_reason[reason] = n;
      t.warning = need(d.warning, "warning");
      t.density = d.density_all().value_or(-1);
    } else {
      t.by_reason["none"] = need(d.none, "none");
      t.by_reason["failed"] = need(d.failed, "failed");
    }
    int rejected = 0;
    for (const auto& [reason, n] : t.by_reason) rejected += n;
    if (t.found != static_cast<int>(dets.size()) || t.candidates != t.found + rejected) {
      throw MalformedField("candidates " + std::to_string(t.candidates) + " is not found " +
                           std::to_string(t.found) + " + the rejected " + std::to_string(rejected) +
                           " (or found is not the " + std::to_string(dets.size()) + " detections)");
    }
  } catch (const MalformedField& e) { throw common::DataError(path, e.what()); }
}

// detect's index: the tile's points, its grid's area, its density when detect gives it.
void read_index(const std::string& path, RealTile& t) {
  const documents::Candidates x = documents::read_candidates_file(path);
  if (!x.tile_points) throw common::DataError(path, "index: missing \"tile_points\"");
  if (!x.ground) throw common::DataError(path, "index: missing \"ground\"");
  t.points = *x.tile_points;
  const double area_m2 = x.ground->cell * x.ground->cell * static_cast<double>(x.ground->cells);
  if (!t.labelled && area_m2 > 0) {
    t.area_ha = area_m2 / 1e4;
    t.area_from = "detect's grid (bounding box)";
  }
  if (t.density < 0) t.density = x.density_all().value_or(-1);
  if (t.density > 0) {
    t.density_from = "index";
  } else if (area_m2 > 0 && t.points > 0) {
    t.density = t.points / area_m2;
    t.density_from = "measured (points / bounding box)";
  }
}

// The first line holding "error:" in the tile's stage logs (<dir>/*.log, by name), cut to 300
// characters; "" when none has one.
std::string first_error(const std::string& dir) {
  std::vector<fs::path> logs;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.is_regular_file() && e.path().extension() == ".log") logs.push_back(e.path());
  }
  std::sort(logs.begin(), logs.end());
  for (const auto& log : logs) {
    std::istringstream in(common::read_file(log.string()));
    for (std::string line; std::getline(in, line);) {
      if (line.find("error:") != std::string::npos)
        return line.size() > 300 ? line.substr(0, 300) + "…" : line;
    }
  }
  return "";
}

struct Uncertain {
  double x = 0, y = 0;
};

// The labels: vehicles (visibility), uncertain objects' centres, the extent's area.
void read_truth(const std::string& path, RealTile& t, std::map<int, bool>& clear, std::vector<Uncertain>& unc) {
  const documents::SceneTruth j = documents::read_scene_truth_file(path);
  if (!j.extent) throw common::DataError(path, "missing \"extent\"");
  for (const documents::TrueVehicle& v : j.vehicles)
    clear[static_cast<int>(v.instance)] = v.visibility == "clear";
  t.vehicles = static_cast<int>(clear.size());
  for (const auto& [id, c] : clear) t.clear += c ? 1 : 0;
  for (const documents::UncertainObject& u : j.uncertain) unc.push_back({u.x, u.y});
  t.uncertain = static_cast<int>(unc.size());
  t.area_ha = (*j.extent)[0] * (*j.extent)[1] / 1e4;
  t.area_from = "labels' extent";
}

// score.json against the labels: recall (all, clear), precision without the detections on
// uncertain objects, the class (group) of the matched detections.
void read_score(const std::string& path, RealTile& t, const std::map<int, bool>& clear,
                const std::vector<Uncertain>& unc, const std::map<std::string, std::string>& group) {
  const documents::SceneScore s = documents::read_scene_score_file(path);
  try {
    if (!s.has_params) throw MalformedField("score: missing \"params\"");
    if (!s.params.match_radius_m) throw MalformedField("params: missing \"match_radius_m\"");
    t.match_radius_m = *s.params.match_radius_m;
    std::set<int> matched;
    int detections = 0;
    for (std::size_t i = 0; i < s.matches.size(); ++i) {
      const documents::ScoreMatch& r = s.matches[i];
      const std::string w = "matches[" + std::to_string(i) + "]";
      if (r.outcome == "missed") {
        if (!r.instance) throw MalformedField(w + ": missing \"instance\"");
        const auto c = clear.find(static_cast<int>(*r.instance));
        if (c == clear.end())
          throw MalformedField(w + " names vehicle " + std::to_string(*r.instance) + ", not in the labels");
        const std::string fate = fate_label(r);
        t.lost_all[fate]++;
        if (c->second) t.lost_clear[fate]++;
        if (r.fate_density) t.refused_density.push_back(*r.fate_density);
        continue;
      }
      ++detections;
      if (r.outcome == "false_alarm") {
        ++t.fp;
        if (!r.x) throw MalformedField(w + ": missing \"x\"");
        if (!r.y) throw MalformedField(w + ": missing \"y\"");
        for (const Uncertain& u : unc) {
          if (std::hypot(*r.x - u.x, *r.y - u.y) <= t.match_radius_m) {
            ++t.fp_on_uncertain;
            break;
          }
        }
        continue;
      }
      ++t.tp;
      if (*r.instance > 1000000000)
        throw MalformedField(w + ".instance is not a count: " + std::to_string(*r.instance));
      matched.insert(static_cast<int>(*r.instance));
      const auto g = group.find(*r.candidate);
      if (g == group.end() || g->second.empty()) {
        ++t.matched_without_group;
      } else {
        t.class_right.n++;
        if (g->second == r.true_model.value_or("")) t.class_right.k++;
      }
    }
    t.recall_all = {0, t.vehicles};
    t.recall_clear = {0, t.clear};
    for (int id : matched) {
      const auto c = clear.find(id);
      if (c == clear.end())
        throw MalformedField("matches name vehicle " + std::to_string(id) + ", not in the labels");
      t.recall_all.k++;
      if (c->second) t.recall_clear.k++;
    }
    t.precision = {t.tp, detections - t.fp_on_uncertain};
    if (s.tiles.size() == 1 && s.tiles[0].area_ha) t.area_ha = *s.tiles[0].area_ha;
    t.scored = true;
  } catch (const MalformedField& e) { throw common::DataError(path, e.what()); }
}

}  // namespace

std::string real_tile_source(const std::string& name) {
  if (name.rfind("ahn3_", 0) == 0) return "AHN3 2014, Delft (CC0)";
  if (name == "ign_stbarth_100m") return "IGN, Saint-Barthélemy (Etalab 2.0)";
  if (name.rfind("ign_lidarhd", 0) == 0) return "IGN LiDAR HD (Etalab 2.0)";
  if (name == "forest_lareunion") return "IGN, La Réunion forest (Etalab 2.0)";
  if (name.rfind("forest_ign_loiret", 0) == 0) return "IGN LiDAR HD, Loiret forest (Etalab 2.0)";
  if (name.rfind("forest_neon_teak_", 0) == 0) return "NEON AOP 2018, Teakettle (CC0)";
  if (name.rfind("forest_neon_osbs_", 0) == 0) return "NEON AOP 2018, Ordway-Swisher (CC0)";
  if (name == "forest_bcts_1") return "lasR example, BC conifer forest (GPL-3, REAL_DATA)";
  return "–";
}

RealTile read_real_tile(const RealTileFiles& f) {
  RealTile t;
  t.name = f.name;
  t.labelled = !f.truth.empty();
  t.time = documents::read_stage_time(f.dir + "/tile");
  t.ran = t.time.present;
  // Every stage's .time under the tile's directory but the whole run's.
  std::error_code ec;
  if (fs::is_directory(f.dir, ec)) {
    std::vector<std::string> times;
    for (const auto& e : fs::recursive_directory_iterator(f.dir, ec)) {
      const std::string p = e.path().string();
      if (e.is_regular_file() && e.path().extension() == ".time" && e.path().filename() != "tile.time")
        times.push_back(p.substr(0, p.size() - 5));
    }
    std::sort(times.begin(), times.end());
    for (const auto& artifact : times) {
      const documents::StageTime st = documents::read_stage_time(artifact);
      if (!st.present) continue;
      ++t.stage_runs;
      t.stages_cpu += st.cpu_seconds();
    }
  }
  std::map<int, bool> clear;
  std::vector<Uncertain> unc;
  if (t.labelled) read_truth(f.truth, t, clear, unc);
  std::map<std::string, std::string> group;
  t.finished = exists(f.dir + "/detections.json");
  if (t.ran && !t.finished) t.error = first_error(f.dir);
  if (t.finished) read_detections(f.dir + "/detections.json", t, group);
  if (exists(f.dir + "/cands/index.json")) read_index(f.dir + "/cands/index.json", t);
  if (t.finished && t.labelled && exists(f.dir + "/score.json"))
    read_score(f.dir + "/score.json", t, clear, unc, group);
  return t;
}

namespace {

// "k/n = r% [lo, hi]" with Wilson's 95% interval (every labelled vehicle its own unit); "0/0 –"
// when n = 0.
std::string rate(const Count& c) { return c.n == 0 ? "0/0 –" : rate_ci_units(c.k, c.n, c.n); }

std::string joined(const std::map<std::string, int>& m) {
  std::string s;
  for (const auto& [k, n] : m) {
    if (n == 0) continue;
    s += (s.empty() ? "" : ", ") + k + " " + std::to_string(n);
  }
  return s.empty() ? "–" : s;
}

// Markdown table cells must not break the row.
std::string cell(std::string s) {
  std::replace(s.begin(), s.end(), '|', '/');
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

std::string state(const RealTile& t, int timeout_s) {
  if (!t.ran) return "not run";
  if (!t.finished && !t.error.empty()) return "**failed**: `" + cell(t.error) + "`";
  if (!t.finished)
    return "**not finished** within the time box" +
           (timeout_s > 0 ? " of " + std::to_string(timeout_s) + " s" : "");
  return "";
}

// A labelled tile's counts added to `sum` (the "all scored" rows).
void add_tile(RealTile& sum, const RealTile& t) {
  const auto add = [](Count& to, const Count& c) {
    to.k += c.k;
    to.n += c.n;
  };
  sum.vehicles += t.vehicles;
  sum.clear += t.clear;
  sum.uncertain += t.uncertain;
  sum.found += t.found;
  sum.tp += t.tp;
  sum.fp += t.fp;
  sum.fp_on_uncertain += t.fp_on_uncertain;
  add(sum.recall_all, t.recall_all);
  add(sum.recall_clear, t.recall_clear);
  add(sum.precision, t.precision);
  add(sum.class_right, t.class_right);
  sum.matched_without_group += t.matched_without_group;
}

void tiles_table(std::ostringstream& md, const std::vector<RealTile>& tiles, int timeout_s) {
  md << "| tile | source | area (ha) | density (pts/m²) | points | candidates | detections (model / class "
        "level) | "
        "detections by class | rejected by reason | warning |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const RealTile& t : tiles) {
    md << "| " << t.name << (t.labelled ? "" : " (no vehicles)") << " | " << real_tile_source(t.name) << " | "
       << (t.area_ha > 0 ? format_number("%.2f", t.area_ha) : "–") << " | "
       << (t.density > 0 ? format_number("%.1f", t.density) + (t.density_from == "index" ? "" : " (measured)")
                         : "–")
       << " | " << (t.points >= 0 ? std::to_string(t.points) : "–") << " | ";
    const std::string s = state(t, timeout_s);
    if (!s.empty()) {
      md << s << " | | | | |\n";
      continue;
    }
    const auto level = [&](const char* l) {
      const auto it = t.by_level.find(l);
      return it == t.by_level.end() ? 0 : it->second;
    };
    md << t.candidates << " | " << t.found << " (" << level("model") << " / " << level("class") << ") | "
       << joined(t.by_class) << " | " << joined(t.by_reason) << " | " << (t.warning.empty() ? "–" : t.warning)
       << " |\n";
  }
  md << "\n";
}

// Plots of at least this many points per m² (detect's density of all returns) form the forest
// table's dense band: the national surveys' densities (10–30), where the class level has points to
// work with; below it (older or sparser surveys) a plot without false alarms says less.
constexpr double kForestDenseBand = 10;

// A row of the forest table: `alarms` false alarms on `area` ha, "| label | density | area | n |
// per ha | [lo, hi] |" (a plot's, its density given; a total's, the density empty).
void forest_row(std::ostringstream& md, const std::string& label, const std::string& density, double area,
                int alarms) {
  const common::Interval p = common::poisson_exact(alarms);
  md << "| " << label << " |" << (density.empty() ? "" : " " + density) << " | "
     << format_number("%.2f", area) << " | " << alarms << " | " << format_number("%.1f", alarms / area)
     << " | [" << format_number("%.1f", p.lo / area) << ", " << format_number("%.1f", p.hi / area) << "] |\n";
}

void forest_table(std::ostringstream& md, const std::vector<RealTile>& tiles) {
  md << "### Plots without vehicles: false alarms\n\n"
        "Every detection on a plot without vehicles is a false alarm. Per hectare of the plot (detect's "
        "grid: its bounding box), with the **exact Poisson (Garwood) 95% interval** of the count divided by "
        "the area; then over all plots and over the plots at "
     << format_number("%g", kForestDenseBand)
     << " points/m² or more (detect's density of all returns) and under it.\n\n"
        "| plot | density (pts/m²) | area (ha) | false alarms | per ha | 95% interval per ha |\n"
        "|---|---|---|---|---|---|\n";
  double area = 0, dense_area = 0, sparse_area = 0;
  int alarms = 0, dense_alarms = 0, sparse_alarms = 0, plots = 0;
  for (const RealTile& t : tiles) {
    if (t.labelled) continue;
    const std::string density = t.density > 0 ? format_number("%.1f", t.density) : "–";
    if (!t.finished || t.area_ha <= 0) {
      md << "| " << t.name << " | " << density << " | "
         << (t.area_ha > 0 ? format_number("%.2f", t.area_ha) : "–") << " | "
         << (t.ran ? (t.error.empty() ? "not finished" : "failed") : "not run") << " | | |\n";
      continue;
    }
    forest_row(md, t.name, density, t.area_ha, t.found);
    area += t.area_ha;
    alarms += t.found;
    ++plots;
    if (t.density >= kForestDenseBand) {
      dense_area += t.area_ha;
      dense_alarms += t.found;
    } else if (t.density > 0) {
      sparse_area += t.area_ha;
      sparse_alarms += t.found;
    }
  }
  const std::string band = format_number("%g", kForestDenseBand) + " pts/m²";
  if (plots > 1) forest_row(md, "**all plots**", "", area, alarms);
  if (dense_area > 0 && sparse_area > 0) {
    forest_row(md, "plots at " + band + " or more", "", dense_area, dense_alarms);
    forest_row(md, "plots under " + band, "", sparse_area, sparse_alarms);
  }
  md << "\n";
  if (plots == 0) {
    md << "No plot without vehicles finished.\n\n";
    return;
  }
  md << "With " << alarms << (alarms == 1 ? " false alarm on " : " false alarms on ")
     << format_number("%.2f", area) << " ha the 95% interval reaches "
     << format_number("%.1f", common::poisson_exact(alarms).hi / area) << " per ha over all plots";
  if (dense_area > 0 && sparse_area > 0)
    md << ", and " << format_number("%.1f", common::poisson_exact(dense_alarms).hi / dense_area)
       << " per ha over the " << format_number("%.2f", dense_area) << " ha at " << band
       << " or more. Under it classify's class level has few points on an object to decide on (it needs 4 "
          "per m² of the object): a plot there without false alarms says less than one at a survey's density";
  md << ". The issue's target is at most 1 false alarm per ha.\n\n";
}

void urban_table(std::ostringstream& md, const std::vector<RealTile>& tiles) {
  md << "### Urban tiles against the hand labels\n\n"
        "`score` matches a detection to a labelled vehicle within its match radius (one to one, most "
        "confident "
        "first). Recall = labelled vehicles matched / labelled, over all and over the **clear** ones (roof "
        "fully "
        "seen, not under a crown, not merged: docs/decisions/real-tiles.md \"Visibility\"); a detection "
        "within "
        "the match radius of an **uncertain** object is neither a hit nor a false alarm (left out of "
        "precision's "
        "denominator); class = the detection's group (car, van, …) against the label's. Wilson 95% "
        "intervals.\n\n"
        "| tile | labelled (clear) | uncertain | detections | TP | FP (on uncertain) | recall, all | recall, "
        "clear "
        "| precision | class right |\n|---|---|---|---|---|---|---|---|---|---|\n";
  RealTile sum;
  int n = 0;
  for (const RealTile& t : tiles) {
    if (!t.labelled) continue;
    md << "| " << t.name << " | " << t.vehicles << " (" << t.clear << ") | " << t.uncertain << " | ";
    if (!t.scored) {
      md << (t.finished        ? "not scored"
             : !t.ran          ? "not run"
             : t.error.empty() ? "not finished"
                               : "failed")
         << " | | | | | | |\n";
      continue;
    }
    md << t.found << " | " << t.tp << " | " << t.fp << " (" << t.fp_on_uncertain << ") | "
       << rate(t.recall_all) << " | " << rate(t.recall_clear) << " | " << rate(t.precision) << " | "
       << rate(t.class_right)
       << (t.matched_without_group > 0 ? " (" + std::to_string(t.matched_without_group) + " without a group)"
                                       : "")
       << " |\n";
    add_tile(sum, t);
    ++n;
  }
  if (n > 1) {
    md << "| **all scored** | " << sum.vehicles << " (" << sum.clear << ") | " << sum.uncertain << " | "
       << sum.found << " | " << sum.tp << " | " << sum.fp << " (" << sum.fp_on_uncertain << ") | "
       << rate(sum.recall_all) << " | " << rate(sum.recall_clear) << " | " << rate(sum.precision) << " | "
       << rate(sum.class_right)
       << (sum.matched_without_group > 0
               ? " (" + std::to_string(sum.matched_without_group) + " without a group)"
               : "")
       << " |\n";
  }
  md << "\n";
}

// Where the labelled vehicles no detection matched were lost (score's fate of each missed
// vehicle): one row per fate, one column per scored tile ("clear (all)"), and the total.
void lost_table(std::ostringstream& md, const std::vector<RealTile>& tiles) {
  std::vector<const RealTile*> scored;
  std::map<std::string, int> total_clear, total_all;
  std::vector<double> densities;
  for (const RealTile& t : tiles) {
    if (!t.labelled || !t.scored) continue;
    scored.push_back(&t);
    for (const auto& [f, n] : t.lost_all) total_all[f] += n;
    for (const auto& [f, n] : t.lost_clear) total_clear[f] += n;
    densities.insert(densities.end(), t.refused_density.begin(), t.refused_density.end());
  }
  if (scored.empty()) return;
  md << "### Where the labelled vehicles were lost\n\n"
        "Every labelled vehicle that no detection matched, by `score`'s fate (formats/README.md \"Scene "
        "score\"): the candidate whose centre is nearest the vehicle's, within the match radius or inside "
        "its outline, decides — none: **no candidate** (detect made none there, or only one centred "
        "elsewhere, e.g. merged into something larger); a rejection: **refused**, with its reason "
        "(classify's, "
        "or the model chain's); a detection that matched another vehicle: **taken** (one answer for two "
        "vehicles); an unmatched detection: **off centre**. Per tile: clear vehicles lost (all lost).\n\n"
        "| fate |";
  for (const RealTile* t : scored) md << " " << t->name << " |";
  md << " all scored |\n|---|";
  for (std::size_t i = 0; i <= scored.size(); ++i) md << "---|";
  md << "\n";
  std::vector<std::string> fates;
  for (const auto& [f, n] : total_all) fates.push_back(f);
  std::stable_sort(fates.begin(), fates.end(),
                   [&](const std::string& a, const std::string& b) { return total_all[a] > total_all[b]; });
  const auto cell = [](const std::map<std::string, int>& clear, const std::map<std::string, int>& all,
                       const std::string& f) {
    const auto c = clear.find(f);
    const auto a = all.find(f);
    return std::to_string(c == clear.end() ? 0 : c->second) + " (" +
           std::to_string(a == all.end() ? 0 : a->second) + ")";
  };
  for (const std::string& f : fates) {
    md << "| " << f << " |";
    for (const RealTile* t : scored) md << " " << cell(t->lost_clear, t->lost_all, f) << " |";
    md << " " << cell(total_clear, total_all, f) << " |\n";
  }
  const auto sum = [](const std::map<std::string, int>& m) {
    int n = 0;
    for (const auto& [f, k] : m) n += k;
    return n;
  };
  md << "| **lost** |";
  for (const RealTile* t : scored) md << " " << sum(t->lost_clear) << " (" << sum(t->lost_all) << ") |";
  md << " " << sum(total_clear) << " (" << sum(total_all) << ") |\n\n";
  if (!densities.empty()) {
    std::sort(densities.begin(), densities.end());
    md << "Object density of the refused candidates of lost vehicles (points per m²): median "
       << format_number("%.1f", common::sorted_quantile(densities, 0.5)) << ", quartiles "
       << format_number("%.1f", common::sorted_quantile(densities, 0.25)) << "–"
       << format_number("%.1f", common::sorted_quantile(densities, 0.75)) << ", range "
       << format_number("%.1f", densities.front()) << "–" << format_number("%.1f", densities.back()) << " ("
       << densities.size() << (densities.size() == 1 ? " candidate" : " candidates") << ").\n\n";
  }
}

void time_table(std::ostringstream& md, const std::vector<RealTile>& tiles, double target_s) {
  md << "### Time per tile\n\n"
        "The whole workflow of a tile (`tile.time`: GNU time around its make, so every stage under it; the "
        "tiles "
        "run one after another, each with make's job slots for its candidates): wall time (on a shared "
        "machine "
        "it includes waiting for the CPU) and CPU (user + system), against the target of "
     << format_number("%g", target_s)
     << " s wall per tile; beside them the CPU summed over the tile's stage `.time` files (a stage that "
        "failed writes none; the rest of the run's CPU is make's). A tile runs from scratch whenever it "
        "re-runs, so these are a whole run's times.\n\n"
        "| tile | wall s | CPU s | stages' CPU s (files) | wall ≤ "
     << format_number("%g", target_s) << " s |\n|---|---|---|---|---|\n";
  for (const RealTile& t : tiles) {
    md << "| " << t.name << " | ";
    if (!t.ran) {
      md << "not run | | | |\n";
      continue;
    }
    md << format_number("%.1f", t.time.seconds)
       << (t.finished        ? ""
           : t.error.empty() ? " (stopped)"
                             : " (failed)")
       << " | " << (t.time.has_cpu ? format_number("%.1f", t.time.cpu_seconds()) : "–") << " | "
       << format_number("%.1f", t.stages_cpu) << " (" << t.stage_runs << ") | "
       << (t.finished && t.time.seconds <= target_s ? "yes" : "**no**") << " |\n";
  }
  md << "\n";
}

// One tile's run as the ablation table shows it: "" when it finished (and, labelled, was scored),
// else what happened.
std::string run_state(const RealTile& t) {
  if (!t.ran) return "not run";
  if (!t.finished) return t.error.empty() ? "not finished" : "failed";
  if (t.labelled && !t.scored) return "not scored";
  return "";
}

// A plot's false alarms: "n = x per ha [lo, hi]" (exact Poisson).
std::string alarms(const RealTile& t) {
  if (t.area_ha <= 0) return std::to_string(t.found);
  const common::Interval p = common::poisson_exact(t.found);
  return std::to_string(t.found) + " = " + format_number("%.1f", t.found / t.area_ha) + "/ha [" +
         format_number("%.1f", p.lo / t.area_ha) + ", " + format_number("%.1f", p.hi / t.area_ha) + "]";
}

}  // namespace

std::string real_ablation_markdown(const std::vector<RealTile>& tiles, const std::vector<RealTile>& ablation,
                                   const std::string& config, int index) {
  if (ablation.empty()) return "";
  const std::string place =
      "mk/real.mk REAL_CLASSIFY_ABLATION" + (index > 0 ? "_" + std::to_string(index + 1) : "");
  const bool model_level = model_level_entry(config);
  std::ostringstream md;
  if (model_level) {
    md << "### The model level's ablation on the real tiles\n\n"
          "The same tiles through the same workflow with classify.ini and `"
       << config
       << "` (points/m² of object from which a candidate also runs the model chain; canopy's is "
          "mk/scenes.mk's TILE_MODEL_DENSITY; docs/decisions/density-scale.md; "
       << place
       << "), run after canopy's, scored the same way: the detections at the model level, recall over the "
          "clear and over all labelled vehicles, precision and class right on the urban tiles (Wilson 95%), "
          "false alarms on the plots without vehicles (exact Poisson 95%).\n\n";
  } else {
    md << "### classify's " << ablation_name(index <= 0 ? 1 : index + 1)
       << " on the real tiles\n\n"
          "The same tiles through the same workflow with classify's parameters `"
       << config << "` (the file's header says which default it turns off; " << place
       << "), run "
          "after canopy's, scored the same way: recall over the clear and over all labelled vehicles, "
          "precision and class right on the urban tiles (Wilson 95%), false alarms on the plots without "
          "vehicles (exact Poisson 95%).\n\n";
  }
  md << "| tile | measure | canopy | ablation |\n|---|---|---|---|\n";
  const auto model_count = [](const RealTile& t) {
    const auto m = t.by_level.find("model");
    return m == t.by_level.end() ? 0 : m->second;
  };
  int model_c = 0, model_a = 0;
  RealTile sum_c, sum_a;
  int both = 0;
  for (const RealTile& a : ablation) {
    const auto c =
        std::find_if(tiles.begin(), tiles.end(), [&](const RealTile& t) { return t.name == a.name; });
    if (c == tiles.end()) continue;
    const std::string sc = run_state(*c), sa = run_state(a);
    if (!sc.empty() || !sa.empty()) {
      md << "| " << a.name << " | run | " << (sc.empty() ? "finished" : sc) << " | "
         << (sa.empty() ? "finished" : sa) << " |\n";
      continue;
    }
    if (model_level) {
      md << "| " << a.name << (a.labelled ? "" : " (no vehicles)") << " | model level detections | "
         << model_count(*c) << " | " << model_count(a) << " |\n";
      model_c += model_count(*c);
      model_a += model_count(a);
    }
    if (!a.labelled) {
      md << "| " << a.name << " (no vehicles) | false alarms | " << alarms(*c) << " | " << alarms(a) << " |\n";
      continue;
    }
    md << "| " << a.name << " | recall, clear | " << rate(c->recall_clear) << " | " << rate(a.recall_clear)
       << " |\n"
       << "| " << a.name << " | recall, all | " << rate(c->recall_all) << " | " << rate(a.recall_all) << " |\n"
       << "| " << a.name << " | precision | " << rate(c->precision) << " | " << rate(a.precision) << " |\n"
       << "| " << a.name << " | class right | " << rate(c->class_right) << " | " << rate(a.class_right)
       << " |\n";
    add_tile(sum_c, *c);
    add_tile(sum_a, a);
    ++both;
  }
  if (both > 1) {
    md << "| **all scored** | recall, clear | " << rate(sum_c.recall_clear) << " | "
       << rate(sum_a.recall_clear) << " |\n"
       << "| **all scored** | recall, all | " << rate(sum_c.recall_all) << " | " << rate(sum_a.recall_all)
       << " |\n"
       << "| **all scored** | precision | " << rate(sum_c.precision) << " | " << rate(sum_a.precision) << " |\n"
       << "| **all scored** | class right | " << rate(sum_c.class_right) << " | " << rate(sum_a.class_right)
       << " |\n";
  }
  if (model_level)
    md << "| **all tiles** | model level detections | " << model_c << " | " << model_a << " |\n";
  md << "\n";
  return md.str();
}

std::string real_markdown(const std::vector<RealTile>& tiles, int timeout_s, double target_s) {
  std::ostringstream md;
  std::vector<std::string> plots, urban;
  for (const RealTile& t : tiles) {
    const std::string s = t.finished        ? ""
                          : !t.ran          ? " (not run)"
                          : t.error.empty() ? " (not finished)"
                                            : " (failed)";
    (t.labelled ? urban : plots).push_back(t.name + s);
  }
  const auto list = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s.empty() ? std::string("none") : s;
  };
  md << "## Real tiles (issue 26)\n\n"
        "The tile workflow (`make tile`, mk/scenes.mk) on real airborne LiDAR tiles (share/real/: sources "
        "and "
        "licences in its README) with the experiment's modelbase; mk/real.mk, docs/decisions/real-tiles.md. "
        "Urban tiles with hand-labelled vehicles: "
     << list(urban) << ". Plots without vehicles: " << list(plots) << "."
     << (std::find_if(tiles.begin(), tiles.end(),
                      [](const RealTile& t) { return t.name == "forest_bcts_1"; }) == tiles.end()
             ? " The GPL-3 plot forest_bcts_1 is not committed and runs only with `REAL_DATA=<dir>`: not run "
               "here."
             : "")
     << " Each tile is time-boxed"
     << (timeout_s > 0 ? " at " + std::to_string(timeout_s) + " s wall (REAL_TIMEOUT)" : std::string())
     << ". Few and small tiles: the figures are indications with wide intervals, not rates to plan with.\n\n";
  tiles_table(md, tiles, timeout_s);
  forest_table(md, tiles);
  urban_table(md, tiles);
  lost_table(md, tiles);
  time_table(md, tiles, target_s);
  return md.str();
}

}  // namespace canopy::report
