// The report's scene-experiment section: stage times from the .time files, and the Markdown
// rendering of score.json (whose numbers `score` computed).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "canopy/common/error.h"
#include "report/report.h"

namespace canopy::report {
namespace {

using Json = nlohmann::ordered_json;

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// A rate of the score (a number or null) as a percentage; null = "–".
std::string rate(const Json& v) { return v.is_number() ? fmt("%.1f%%", 100 * v.get<double>()) : "–"; }
std::string num(const Json& v, const char* f) { return v.is_number() ? fmt(f, v.get<double>()) : "–"; }
std::string text(const Json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_integer()) return std::to_string(v.get<long long>());
  if (v.is_number()) return fmt("%g", v.get<double>());
  return "–";
}

bool read_time(const std::string& path, double& seconds, double& peak_mb) {
  std::ifstream in(path);
  double s = 0, kib = 0;
  if (!(in >> s >> kib)) return false;
  seconds = s;
  peak_mb = kib / 1024.0;
  return true;
}

const Json& field(const Json& j, const char* key) {
  static const Json null_value = nullptr;
  const auto it = j.find(key);
  return it == j.end() ? null_value : *it;
}

}  // namespace

std::vector<SceneRun> scene_runs(const Json& score) {
  std::vector<SceneRun> runs;
  if (!score.contains("tiles") || !score["tiles"].is_array()) return runs;
  for (const Json& t : score["tiles"]) {
    SceneRun r;
    r.dir = std::filesystem::path(t.value("detections", std::string())).parent_path().string();
    r.area_ha = t.value("area_ha", 0.0);
    runs.push_back(r);
  }
  return runs;
}

std::vector<SceneStageTime> scene_times(const std::vector<SceneRun>& runs) {
  const std::vector<std::pair<std::string, std::string>> per_candidate = {{"fitvox", "samples.pcd"},
                                                                          {"cocone", "mesh.ply"},
                                                                          {"ncut", "segments.json"},
                                                                          {"gmatch", "match.json"},
                                                                          {"verify", "verdict.json"}};
  std::vector<SceneStageTime> out;
  for (const char* s : {"rangetrace", "addnoise", "detect", "plan", "fitvox", "cocone", "ncut", "gmatch",
                        "verify", "collect", "topview"}) {
    SceneStageTime t;
    t.stage = s;
    out.push_back(t);
  }
  auto at = [&](const std::string& stage) -> SceneStageTime& {
    for (auto& t : out) {
      if (t.stage == stage) return t;
    }
    throw common::Error("scene_times: no stage " + stage);
  };
  auto add = [&](const std::string& stage, const std::string& path) {
    double s = 0, mb = 0;
    if (!read_time(path + ".time", s, mb)) return;
    SceneStageTime& t = at(stage);
    t.runs++;
    t.seconds += s;
    t.peak_mb = std::max(t.peak_mb, mb);
  };
  std::set<std::string> renders;
  for (const SceneRun& r : runs) {
    const std::string tile = std::filesystem::path(r.dir).parent_path().string();
    if (renders.insert(tile).second) {
      add("rangetrace", tile + "/scan.pcd");
      at("rangetrace").area_ha += r.area_ha;
    }
    add("addnoise", r.dir + "/scan.pcd");
    add("detect", r.dir + "/detect");
    add("plan", r.dir + "/cands.mk");
    add("collect", r.dir + "/detections.json");
    add("topview", r.dir + "/scored.png");
    std::vector<std::string> cands;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(r.dir + "/cands", ec)) {
      if (e.is_directory()) cands.push_back(e.path().string());
    }
    std::sort(cands.begin(), cands.end());
    for (const auto& c : cands) {
      for (const auto& [stage, file] : per_candidate) add(stage, c + "/" + file);
    }
    for (auto& t : out) {
      if (t.stage != "rangetrace") t.area_ha += r.area_ha;
    }
  }
  for (auto& t : out) t.per_ha = t.area_ha > 0 ? t.seconds / t.area_ha : 0;
  return out;
}

std::string scene_times_csv(const std::vector<SceneStageTime>& times) {
  std::ostringstream csv;
  csv << "stage,runs,seconds,area_ha,seconds_per_ha,peak_mb\n";
  for (const auto& t : times) {
    csv << t.stage << "," << t.runs << "," << fmt("%.2f", t.seconds) << "," << fmt("%.4f", t.area_ha) << ","
        << fmt("%.2f", t.per_ha) << "," << fmt("%.1f", t.peak_mb) << "\n";
  }
  return csv.str();
}

std::string scene_markdown(const Json& score, const std::vector<SceneStageTime>& times, const std::string& fig) {
  std::ostringstream md;
  const Json& tiles = field(score, "tiles");
  const Json& summary = field(score, "summary");
  std::vector<std::string> covers;
  std::set<std::string> renders;
  for (const Json& t : tiles) {
    const std::string c = text(field(t, "cover"));
    if (std::find(covers.begin(), covers.end(), c) == covers.end() && c != "–") covers.push_back(c);
    renders.insert(
        std::filesystem::path(t.value("detections", std::string())).parent_path().parent_path().string());
  }
  const Json* all = nullptr;
  for (const Json& s : summary) {
    if (text(field(s, "cover")) == "all" && text(field(s, "noise_mm")) == "all") all = &s;
  }
  md << "## Scene experiment (issue 16)\n\n";
  md << "Whole tiles (docs/decisions/scene-experiment.md): " << renders.size() << " rendered tiles, "
     << tiles.size() << " runs (tile × noise level)";
  if (all != nullptr) {
    md << ", " << fmt("%.2f", field(*all, "area_ha").get<double>()) << " ha in all, "
       << text(field(*all, "true")) << " true vehicles, " << text(field(*all, "candidates"))
       << " candidates verified";
  }
  md << ". A detection matches a true vehicle whose centre lies within "
     << num(field(field(score, "params"), "match_radius_m"), "%g")
     << " m of its own (one to one, most confident first); identification = right model among the matched "
        "detections; recognition = right model found / true vehicles; pose errors over the identified "
        "detections. Tables: `scenes/*.csv`.\n\n";

  md << "### Detection, identification and pose\n\n"
        "| cover | noise (mm) | tiles | mean vehicle cover | true | candidates | detections | TP | FP | FN | "
        "precision | recall | F1 | false alarms / ha | identification | recognition | position error median "
        "/ "
        "p90 (m) | heading error median / p90 (°) | flips |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Json& s : summary) {
    md << "| " << text(field(s, "cover")) << " | " << text(field(s, "noise_mm")) << " | "
       << text(field(s, "tiles")) << " | " << num(field(s, "mean_vehicle_cover"), "%.2f") << " | "
       << text(field(s, "true")) << " | " << text(field(s, "candidates")) << " | "
       << text(field(s, "detections")) << " | " << text(field(s, "tp")) << " | " << text(field(s, "fp"))
       << " | " << text(field(s, "fn")) << " | " << rate(field(s, "precision")) << " | "
       << rate(field(s, "recall")) << " | " << rate(field(s, "f1")) << " | "
       << num(field(s, "false_alarms_per_ha"), "%.1f") << " | " << rate(field(s, "identification")) << " | "
       << rate(field(s, "recognition")) << " | " << num(field(s, "position_error_median_m"), "%.2f") << " / "
       << num(field(s, "position_error_p90_m"), "%.2f") << " | "
       << num(field(s, "heading_error_median_deg"), "%.1f") << " / "
       << num(field(s, "heading_error_p90_deg"), "%.1f") << " | " << text(field(s, "flips")) << " |\n";
  }
  md << "\n";

  // The targets, judged on the same numbers.
  md << "Targets of the issue (reported whatever they are):\n\n| target | measured | met |\n|---|---|---|\n";
  auto judge = [&](const char* what, const char* key, double bound, bool at_least) {
    std::string measured;
    bool met = true, any = false;
    for (const Json& s : summary) {
      const std::string c = text(field(s, "cover")), n = text(field(s, "noise_mm"));
      if ((c != "light" && c != "medium") || (n != "0" && n != "8")) continue;
      const Json& v = field(s, key);
      measured += (measured.empty() ? "" : ", ") + c + " " + n + " mm " + rate(v);
      any = true;
      if (!v.is_number() || (at_least ? v.get<double>() < bound : v.get<double>() > bound)) met = false;
    }
    md << "| " << what << " | " << (any ? measured : "no light/medium run at 0–8 mm") << " | "
       << (any ? (met ? "yes" : "**no**") : "–") << " |\n";
  };
  judge("recall ≥ 95% at light and medium cover, 0–8 mm", "recall", 0.95, true);
  judge("precision ≥ 95% at light and medium cover, 0–8 mm", "precision", 0.95, true);
  if (all != nullptr) {
    const Json& id = field(*all, "identification");
    md << "| identification ≥ 90% of matched detections (all runs) | " << rate(id) << " | "
       << (id.is_number() ? (id.get<double>() >= 0.9 ? "yes" : "**no**") : "–") << " |\n";
    const Json& he = field(*all, "heading_error_median_deg");
    md << "| heading error median ≤ 2° (all runs) | " << num(he, "%.2f°") << " | "
       << (he.is_number() ? (he.get<double>() <= 2 ? "yes" : "**no**") : "–") << " |\n";
  }
  md << "\n";

  md << "### Identification per model\n\n"
        "| model | cover | true | matched | identified | recall | identification | recognition |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const Json& m : field(score, "models")) {
    md << "| " << text(field(m, "model")) << " | " << text(field(m, "cover")) << " | "
       << text(field(m, "true")) << " | " << text(field(m, "matched")) << " | "
       << text(field(m, "identified")) << " | " << rate(field(m, "recall")) << " | "
       << rate(field(m, "identification")) << " | " << rate(field(m, "recognition")) << " |\n";
  }
  md << "\n";

  md << "### Recognition against the measured canopy cover\n\n"
        "Per vehicle, the share of its footprint under vegetation seen from straight above (rangetrace's "
        "nadir image, `canopy_cover` in truth.json), binned; all noise levels, then per noise level.\n\n"
        "| canopy cover | noise (mm) | true | detected | recognised | recall | recognition |\n"
        "|---|---|---|---|---|---|---|\n";
  for (const Json& b : field(score, "cover_bins")) {
    md << "| " << num(field(b, "cover_lo"), "%.2f") << "–" << num(field(b, "cover_hi"), "%.2f") << " | "
       << text(field(b, "noise_mm")) << " | " << text(field(b, "true")) << " | " << text(field(b, "detected"))
       << " | " << text(field(b, "recognised")) << " | " << rate(field(b, "recall")) << " | "
       << rate(field(b, "recognition")) << " |\n";
  }
  md << "\n![recognition against canopy cover](" << fig << "/cover.png)\n\n![recognition against noise]("
     << fig << "/noise.png)\n\n";

  // Precision-recall: at most 12 rows (every k-th threshold and the last); all of it in pr.csv.
  const Json& pr = field(score, "pr");
  md << "### Precision and recall over the confidence\n\n";
  if (pr.empty()) {
    md << "No detection: no curve.\n\n";
  } else {
    md << "Detections at or above each confidence threshold (all runs; " << pr.size()
       << " thresholds, every one in `scenes/pr.csv`).\n\n| confidence ≥ | detections | TP | FP | precision "
          "| recall |\n"
          "|---|---|---|---|---|---|\n";
    const std::size_t step = (pr.size() + 11) / 12;
    for (std::size_t i = 0; i < pr.size(); ++i) {
      if (i % step != 0 && i + 1 != pr.size()) continue;
      const Json& r = pr[i];
      md << "| " << num(field(r, "threshold"), "%.3f") << " | " << text(field(r, "detections")) << " | "
         << text(field(r, "tp")) << " | " << text(field(r, "fp")) << " | " << rate(field(r, "precision"))
         << " | " << rate(field(r, "recall")) << " |\n";
    }
    md << "\n";
  }

  md << "### Time per hectare and peak memory per stage\n\n"
        "Wall time summed over the stage's runs (scripts/stage.sh's `.time` files; on a shared machine "
        "wall time includes waiting for the CPU), per hectare of rendered tiles (rangetrace) or of runs "
        "(every other stage); peak memory of the largest run. `scenes/times.csv`.\n\n"
        "| stage | runs | wall s | s per ha | peak MB |\n|---|---|---|---|---|\n";
  double total = 0;
  for (const auto& t : times) {
    md << "| " << t.stage << " | " << t.runs << " | " << fmt("%.1f", t.seconds) << " | "
       << fmt("%.1f", t.per_ha) << " | " << fmt("%.0f", t.peak_mb) << " |\n";
    total += t.seconds;
  }
  md << "| **all** | | **" << fmt("%.1f", total) << "** | | |\n\n";

  md << "### The tiles from above\n\n"
        "Per cover level: rows = noise levels, columns = the first tiles; outlines: right model green, wrong "
        "model orange, false alarm magenta, missed vehicle yellow, found vehicle's true footprint white.\n\n";
  for (const auto& c : covers) md << "![" << c << " cover](" << fig << "/top-" << c << ".png)\n\n";
  return md.str();
}

}  // namespace canopy::report
