// The scene experiment's runs and the time, CPU and peak memory of its stages from the stage
// runner's .time files, and how many models its verify runs checked (report.h: scene_runs,
// scene_times, scene_times_csv, scene_ranked_models).
#include <algorithm>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/scene_score.h"
#include "canopy/documents/stage_time.h"
#include "canopy/documents/verdict.h"
#include "report/report.h"

namespace canopy::report {

using documents::SceneScore;

std::vector<SceneRun> scene_runs(const SceneScore& score) {
  std::vector<SceneRun> runs;
  for (const documents::ScoreTile& t : score.tiles) {
    SceneRun r;
    r.dir = std::filesystem::path(t.detections).parent_path().string();
    r.area_ha = t.area_ha.value_or(0.0);
    runs.push_back(r);
  }
  return runs;
}

std::vector<SceneStageTime> scene_times(const std::vector<SceneRun>& runs) {
  const std::vector<std::pair<std::string, std::string>> per_candidate = {
      {"classify", "class.json"},
      {"fitvox", "samples.pcd"},
      {"cocone", "mesh.ply"},
      {"ncut", "segments.json"},
      {"gmatch", "match.json"},
      {"verify", "verdict.json"},
      {"baseline-vfh", "baseline-vfh.json"},
      {"baseline-fpfh", "baseline-fpfh.json"},
      {"verify-ablation", "verdict-ablation.json"},
      {"verify-fpfh", "verdict-fpfh.json"}};
  std::vector<SceneStageTime> out;
  for (const char* s :
       {"rangetrace", "addnoise", "detect", "plan", "classify", "fitvox", "cocone", "ncut", "gmatch",
        "verify", "collect", "topview", "baseline-vfh", "baseline-fpfh", "verify-ablation", "verify-fpfh"}) {
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
    const documents::StageTime st = documents::read_stage_time(path);
    if (!st.present) return;
    SceneStageTime& t = at(stage);
    t.runs++;
    t.seconds += st.seconds;
    t.peak_mb = std::max(t.peak_mb, st.peak_mb);
    if (st.has_cpu) {
      t.cpu_runs++;
      t.cpu_seconds += st.cpu_seconds();
    }
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
  // The baseline's and the verify ablations' stages only when they ran (SCENE_BASELINE,
  // SCENE_VERIFY_ABLATION, the FPFH poses' verify).
  out.erase(std::remove_if(out.begin(), out.end(),
                           [](const SceneStageTime& t) { return !canopy_stage(t.stage) && t.runs == 0; }),
            out.end());
  return out;
}

bool canopy_stage(const std::string& stage) {
  return stage.rfind("baseline-", 0) != 0 && stage.rfind("verify-", 0) != 0;
}

std::string scene_times_csv(const std::vector<SceneStageTime>& times) {
  std::ostringstream csv;
  csv << "stage,runs,seconds,area_ha,seconds_per_ha,peak_mb,cpu_seconds,cpu_runs\n";
  for (const auto& t : times) {
    csv << t.stage << "," << t.runs << "," << format_number("%.2f", t.seconds) << ","
        << format_number("%.4f", t.area_ha) << "," << format_number("%.2f", t.per_ha) << ","
        << format_number("%.1f", t.peak_mb) << "," << format_number("%.2f", t.cpu_seconds) << ","
        << t.cpu_runs << "\n";
  }
  return csv.str();
}

SceneRankedModels scene_ranked_models(const SceneScore& score) {
  for (const SceneRun& r : scene_runs(score)) {
    std::error_code ec;
    std::vector<std::filesystem::path> cands;
    for (const auto& e : std::filesystem::directory_iterator(r.dir + "/cands", ec)) cands.push_back(e.path());
    std::sort(cands.begin(), cands.end());
    for (const auto& c : cands) {
      const std::filesystem::path m = c / "match.json", v = c / "verdict.json",
                                  a = c / "verdict-ablation.json";
      const auto filled = [&](const std::filesystem::path& p) {
        return std::filesystem::is_regular_file(p, ec) && std::filesystem::file_size(p, ec) > 0 && !ec;
      };
      if (filled(m) && filled(v))
        return {documents::read_match_result(m.string()).models.size(),
                documents::read_verdict(v.string()).hypotheses.size(),
                filled(a) ? documents::read_verdict(a.string()).hypotheses.size() : 0};
    }
  }
  return {};
}

std::string scene_times_markdown(const std::vector<SceneStageTime>& times) {
  std::ostringstream md;
  md << "### Time per hectare and peak memory per stage\n\n"
        "Wall time summed over the stage's runs (the stage runner's `.time` files, tools/stagerun; on a "
        "shared machine "
        "wall time includes waiting for the CPU) and their CPU time (user + system, which the load does not "
        "change), per hectare of rendered tiles (rangetrace) or of runs (every other stage); peak memory of "
        "the largest run. `scenes/times.csv`.\n\n"
        "| stage | runs | wall s | CPU s | s per ha | peak MB |\n|---|---|---|---|---|---|\n";
  double total = 0, cpu = 0;
  int runs = 0, cpu_runs = 0;
  for (const auto& t : times) {
    md << "| " << t.stage << " | " << t.runs << " | " << format_number("%.1f", t.seconds) << " | "
       << cpu_cell(format_number("%.1f", t.cpu_seconds), t.cpu_runs, t.runs) << " | "
       << format_number("%.1f", t.per_ha) << " | " << format_number("%.0f", t.peak_mb) << " |\n";
    total += t.seconds;
    cpu += t.cpu_seconds;
    runs += t.runs;
    cpu_runs += t.cpu_runs;
  }
  md << "| **all** | | **" << format_number("%.1f", total) << "** | **"
     << cpu_cell(format_number("%.1f", cpu), cpu_runs, runs) << "** | | |\n\n";
  return md.str();
}

}  // namespace canopy::report
