// The scene experiment's runs and the time, CPU and peak memory of its stages from the stage
// runner's .time files (report.h: scene_runs, scene_times, scene_times_csv).
#include <algorithm>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/documents/scene_score.h"
#include "canopy/documents/stage_time.h"
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
                           [](const SceneStageTime& t) {
                             return (t.stage.rfind("baseline-", 0) == 0 || t.stage.rfind("verify-", 0) == 0) &&
                                    t.runs == 0;
                           }),
            out.end());
  return out;
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

}  // namespace canopy::report
