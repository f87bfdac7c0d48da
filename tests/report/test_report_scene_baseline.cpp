// The PCL baseline beside canopy in the report (issue 17): the scene section reads the
// baseline's scores beside canopy's score (<csv dir>/baseline-<method>/score.json) and shows
// them side by side per cover and noise level, per model and per cover bin, judges the issue's
// goal and gives the time per candidate; the thesis baseline section has a per-scene table.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "canopy/documents/experiment_manifest.h"
#include "canopy/documents/match_result.h"
#include "report/baseline_section.h"
#include "canopy/documents/scene_score.h"
#include "report/report.h"
#include "support/cli.h"

using namespace canopy;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) { test::write_file(p, text); }

// A score document over the two runs of one tile, with one summary row per (cover, noise)
// given: recognition r, precision p, heading error h; models and cover bins alike.
std::string score_text(const fs::path& csv_dir, const std::string& run0, const std::string& run1,
                       double r_all, double r_light0, double p_all, double h_all) {
  auto num = [](double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return std::string(b);
  };
  return R"({"format": "canopy.scene_score", "version": 1,
    "provenance": {"tool": "score", "version": "0", "parameters": {"csv": ")" +
         csv_dir.string() + R"(/"}, "inputs": []},
    "params": {"match_radius_m": 1.5},
    "tiles": [{"detections": ")" +
         run0 + R"(/d.json", "cover": "light", "noise_mm": 0, "area_ha": 0.09},
              {"detections": ")" +
         run1 + R"(/d.json", "cover": "light", "noise_mm": 8, "area_ha": 0.09}],
    "summary": [
      {"cover": "all", "noise_mm": "all", "area_ha": 0.18, "true": 10, "detections": 9, "precision": )" +
         num(p_all) + R"(, "recall": 0.9, "identification": 0.5, "recognition": )" + num(r_all) +
         R"(, "position_error_median_m": 0.25, "heading_error_median_deg": )" + num(h_all) + R"(},
      {"cover": "light", "noise_mm": 0, "true": 5, "detections": 5, "precision": 1, "recall": 1,
       "identification": 1, "recognition": )" +
         num(r_light0) + R"(, "position_error_median_m": 0.1, "heading_error_median_deg": 1}],
    "models": [{"model": "tank", "cover": "all", "true": 10, "recognition": )" +
         num(r_all) + R"(}],
    "cover_bins": [{"cover_lo": 0, "cover_hi": 0.5, "noise_mm": "all", "true": 10, "recognition": )" +
         num(r_all) + R"(}],
    "pr": [], "matches": []})";
}

report::SceneStageTime stage_time(const std::string& name, int runs, double seconds) {
  report::SceneStageTime t;
  t.stage = name;
  t.runs = runs;
  t.seconds = seconds;
  return t;
}

}  // namespace

TEST_CASE("scene section: the baseline's scores beside canopy's, the goal, time per candidate",
          "[report][baseline]") {
  const fs::path root = canopy::test::fresh_dir("report", "scene-baseline");
  const fs::path res = root / "results" / "scenes";
  const std::string run0 = (root / "out/scenes/light/tile-1/noise-0").string();
  const std::string run1 = (root / "out/scenes/light/tile-1/noise-8").string();
  const documents::SceneScore score =
      documents::read_scene_score(score_text(res, run0, run1, 0.8, 1.0, 0.9, 1.5), "score.json");
  write(res / "baseline-vfh" / "score.json", score_text(res, run0, run1, 0.4, 0.6, 0.5, 90));
  // FPFH's noise levels written as numbers (0.0) where canopy's are integers (0): the same level.
  std::string fpfh = score_text(res, run0, run1, 0.77, 0.8, 0.95, 2.5);
  for (std::size_t at = fpfh.find("\"noise_mm\": 0,"); at != std::string::npos;
       at = fpfh.find("\"noise_mm\": 0,", at))
    fpfh.replace(at, 14, "\"noise_mm\": 0.0,");
  write(res / "baseline-fpfh" / "score.json", fpfh);
  const std::vector<report::SceneStageTime> times = {
      stage_time("fitvox", 10, 2.0),       stage_time("cocone", 10, 3.0), stage_time("ncut", 10, 1.0),
      stage_time("gmatch", 10, 1.0),       stage_time("verify", 10, 3.0), stage_time("baseline-vfh", 10, 0.5),
      stage_time("baseline-fpfh", 10, 6.0)};
  const std::string md = report::scene_markdown(score, times, "scenes");
  INFO(md);
  REQUIRE(md.find("### canopy beside the PCL baseline (issue 17)") != std::string::npos);
  // Side by side per cover and noise: canopy, then VFH (no heading of its own), then FPFH.
  CHECK(md.find("| all | all | 10 | canopy | 9 | 90.0% | 90.0% | 50.0% | 80.0% | 0.25 | 1.5 |\n"
                "| all | all | 10 | VFH | 9 | 50.0% | 90.0% | 50.0% | 40.0% | 0.25 | – |\n"
                "| all | all | 10 | FPFH | 9 | 95.0% | 90.0% | 50.0% | 77.0% | 0.25 | 2.5 |\n") !=
        std::string::npos);
  CHECK(md.find("| light | 0 | 5 | VFH | 5 | 100.0% | 100.0% | 100.0% | 60.0% | 0.10 | – |") !=
        std::string::npos);
  CHECK(md.find("| light | 0 | 5 | FPFH | 5 | 100.0% | 100.0% | 100.0% | 80.0% | 0.10 | 1.0 |") !=
        std::string::npos);
  CHECK(md.find("| tank | all | 10 | 80.0% | 40.0% | 77.0% |") != std::string::npos);
  CHECK(md.find("| 0.00–0.50 | all | 10 | 80.0% | 40.0% | 77.0% |") != std::string::npos);
  // Goal: 80% against the best baseline (FPFH 77%): +3 points, not met.
  CHECK(md.find("canopy 80.0%, best baseline FPFH 77.0%: +3.0 points, **not met**") != std::string::npos);
  // Time per candidate: canopy 0.2 + 0.3 + 0.1 + 0.1 + 0.3 s; VFH 0.2 + 0.05; FPFH 0.2 + 0.6.
  CHECK(md.find("canopy 1.00 s (fitvox 0.20 + cocone + ncut + gmatch + verify); VFH 0.25 s (fitvox + 0.05 s "
                "baseline, 10 runs); FPFH 0.80 s (fitvox + 0.60 s baseline, 10 runs).") != std::string::npos);

  // The size-only ablation: a row of its own (no heading), left out of the baseline goal even
  // where it does better (85% > FPFH's 77%), compared with canopy in a sentence of its own.
  write(res / "baseline-size" / "score.json", score_text(res, run0, run1, 0.85, 0.7, 0.6, 90));
  const std::string ms = report::scene_markdown(score, times, "scenes");
  INFO(ms);
  CHECK(ms.find("| all | all | 10 | size only (ablation) | 9 | 60.0% | 90.0% | 50.0% | 85.0% | 0.25 | – |") !=
        std::string::npos);
  CHECK(ms.find("canopy 80.0%, best baseline FPFH 77.0%: +3.0 points, **not met**") != std::string::npos);
  CHECK(ms.find("What the model chain adds (issue 29): recognition over all runs, canopy 80.0% against size "
                "only 85.0% (-5.0 points); precision 90.0% against 60.0%.") != std::string::npos);
  // Told which methods ran (report --tile-baselines; mk/scenes.mk), the report reads only theirs:
  // a method turned off is not shown from the score it left, even of canopy's own runs.
  const std::vector<std::string> fpfh_only = {"fpfh"}, none;
  const std::string mf = report::scene_markdown(score, times, "scenes", nullptr, "", {}, {}, &fpfh_only);
  CHECK(mf.find("| all | all | 10 | FPFH | 9 | 95.0% |") != std::string::npos);
  CHECK(mf.find("| VFH |") == std::string::npos);
  CHECK(mf.find("size only (ablation) |") == std::string::npos);
  CHECK(mf.find("canopy 80.0%, best baseline FPFH 77.0%") != std::string::npos);
  CHECK(report::scene_markdown(score, times, "scenes", nullptr, "", {}, {}, &none).find("PCL baseline") ==
        std::string::npos);
  CHECK(report::is_scene_baseline_method("fpfh-verify"));
  CHECK(!report::is_scene_baseline_method("verify-all"));
  fs::remove_all(res / "baseline-size");

  // A baseline score of other runs (a stale experiment) is named, not shown.
  write(res / "baseline-vfh" / "score.json", score_text(res, run0, run0 + "x", 0.4, 0.6, 0.5, 90));
  const std::string md2 = report::scene_markdown(score, times, "scenes");
  CHECK(md2.find("| all | all | 10 | VFH |") == std::string::npos);
  CHECK(md2.find("| all | all | 10 | FPFH |") != std::string::npos);
  CHECK(md2.find("baseline-vfh/score.json scores other runs than canopy's") != std::string::npos);

  // No baseline scores: no baseline subsection.
  fs::remove_all(res);
  CHECK(report::scene_markdown(score, times, "scenes").find("PCL baseline") == std::string::npos);
}

TEST_CASE("scene section: verify with another top-k beside canopy, what gmatch adds and its cost per model",
          "[report][baseline]") {
  // The scene experiment's verify ablation (mk/scenes.mk SCENES_VERIFY_ABLATION: verify again with
  // another top-k): a row of its own beside the baseline's methods, named by its options, left out
  // of issue 17's goal, compared with canopy in a sentence (issue 29); with the CPU per candidate of
  // gmatch, verify and the ablation's verify, the number of models gmatch ranked (a candidate's
  // match.json) and the hypotheses each verify checked (its verdicts), the cost at 100 and 1 000
  // models. Both ways round: canopy on gmatch's top 3 against every model (the ablation when top-k
  // was 3), and canopy on every model against gmatch's top 3 (top-k = 5 on five models).
  const fs::path root = canopy::test::fresh_dir("report", "scene-verify-all");
  const fs::path res = root / "results" / "scenes";
  const std::string run0 = (root / "out/scenes/light/tile-1/noise-0").string();
  const std::string run1 = (root / "out/scenes/light/tile-1/noise-8").string();
  const documents::SceneScore score =
      documents::read_scene_score(score_text(res, run0, run1, 0.8, 1.0, 0.9, 1.5), "score.json");
  // recognition 0.9 > canopy's 0.8: still no baseline (no "best baseline" sentence without one)
  const documents::SceneScore all = documents::read_scene_score(
      score_text(res, run0, run1, 0.9, 1.0, 0.7, 2.0), "verify-ablation/score.json");
  documents::MatchResult m;
  m.error_form = "bounded";
  for (const char* name : {"earthmover", "obj1", "sedan", "semi", "tank"}) {
    documents::ModelScore ms;
    ms.model = name;
    ms.rank = static_cast<int>(m.models.size()) + 1;
    ms.score = 0.9 - 0.1 * ms.rank;
    m.models.push_back(ms);
  }
  fs::create_directories(fs::path(run0) / "cands" / "c0002");
  documents::write_match_result(m, (fs::path(run0) / "cands" / "c0002" / "match.json").string());
  // a verdict that checked gmatch's top k (its hypotheses)
  const auto verdict_of = [&](int k, const char* name) {
    documents::Verdict verdict;
    verdict.candidate = "samples.pcd";
    for (int i = 0; i < k; ++i) {
      documents::Hypothesis h;
      h.model = m.models[static_cast<std::size_t>(i)].model;
      h.gmatch_rank = i + 1;
      verdict.hypotheses.push_back(h);
    }
    documents::write_verdict(verdict, (fs::path(run0) / "cands" / "c0002" / name).string());
  };
  verdict_of(3, "verdict.json");
  verdict_of(5, "verdict-ablation.json");
  // c0001's gmatch failed (stagerun --record-failure: an empty match.json): not read as a ranking
  write(fs::path(run0) / "cands" / "c0001" / "match.json", "");
  auto cpu = [](const std::string& name, int runs, double wall, double cpu_s) {
    report::SceneStageTime t = stage_time(name, runs, wall);
    t.cpu_runs = runs;
    t.cpu_seconds = cpu_s;
    return t;
  };
  const std::vector<report::SceneStageTime> times = {
      cpu("fitvox", 10, 2.0, 2.0), cpu("cocone", 10, 3.0, 3.0), cpu("ncut", 10, 1.0, 1.0),
      cpu("gmatch", 10, 0.5, 0.5), cpu("verify", 10, 3.0, 3.0), cpu("verify-ablation", 10, 5.0, 5.0)};
  const report::SceneVerifyAblation ablation{"--top-k=1000",
                                             (res / "verify-ablation" / "score.json").string(), &all};
  const std::string md = report::scene_markdown(score, times, "scenes", nullptr, "", {}, ablation);
  INFO(md);
  CHECK(md.find("| all | all | 10 | verify `--top-k=1000` (ablation) | 9 | 70.0% | 90.0% | 50.0% | 90.0% | "
                "0.25 | 2.0 |") != std::string::npos);
  CHECK(md.find("best baseline") == std::string::npos);
  CHECK(
      md.find("What gmatch adds (issue 29): canopy's verify checks gmatch's top 3 of the 5 models; verify "
              "again with `--top-k=1000` after its parameters checks every one of the 5 models: recognition "
              "over all runs 90.0% against canopy's 80.0% (-10.0 points for canopy), precision 70.0% against "
              "90.0%.") != std::string::npos);
  // gmatch 0.05 s over 5 models = 0.01 s a model; verify 0.3 s on 3 hypotheses, 0.5 s on 5: one
  // hypothesis (0.5 - 0.3) / 2 = 0.1 s. 100 models: 100 x 0.01 + 0.3 = 1.3 s against 0.3 + 97 x
  // 0.1 = 10 s; 1 000: 10.3 s against 0.3 + 997 x 0.1 = 100 s.
  CHECK(
      md.find("gmatch 0.050 s (0.0100 s a model, at most), verify 0.300 s on gmatch's top 3 of the 5 models, "
              "0.500 s on every one of the 5 models (0.100 s a hypothesis); with N models canopy (top-k = 3) "
              "would cost about N × 0.0100 s + 0.30 s a candidate against 0.30 s + (N − 3) × 0.100 s for "
              "verify over every model: at 100 models 1.3 s against 10.0 s, at 1 000 models 10.3 s against "
              "100.0 s") != std::string::npos);
  CHECK(md.find("saves nothing") == std::string::npos);
  // Time per candidate: fitvox + cocone + ncut + gmatch (0.65 s) + the ablation's verify 0.5 s.
  CHECK(md.find("; verify `--top-k=1000` (ablation) 1.15 s (fitvox + cocone + ncut + gmatch + 0.50 s verify, "
                "10 runs)") != std::string::npos);

  // The other way round: canopy checks every model (top-k 5 of 5; 0.5 s), the ablation gmatch's top
  // 3 (0.3 s): the same 0.1 s a hypothesis; 100 models: 1 + 0.5 = 1.5 s against 0.5 + 95 x 0.1 = 10 s.
  verdict_of(5, "verdict.json");
  verdict_of(3, "verdict-ablation.json");
  const std::vector<report::SceneStageTime> times5 = {
      cpu("fitvox", 10, 2.0, 2.0), cpu("cocone", 10, 3.0, 3.0), cpu("ncut", 10, 1.0, 1.0),
      cpu("gmatch", 10, 0.5, 0.5), cpu("verify", 10, 5.0, 5.0), cpu("verify-ablation", 10, 3.0, 3.0)};
  const std::string m5 =
      report::scene_markdown(score, times5, "scenes", nullptr, "", {}, {"--top-k=3", ablation.path, &all});
  INFO(m5);
  CHECK(m5.find("| all | all | 10 | verify `--top-k=3` (ablation) | 9 | 70.0% |") != std::string::npos);
  CHECK(
      m5.find("What gmatch adds (issue 29): canopy's verify checks every one of the 5 models (its ranking "
              "chooses nothing here; its segment pairs give the start poses); verify again with `--top-k=3` "
              "after its parameters checks gmatch's top 3 of the 5 models: recognition over all runs 90.0% "
              "against canopy's 80.0%") != std::string::npos);
  CHECK(m5.find(
            "verify 0.500 s on every one of the 5 models, 0.300 s on gmatch's top 3 of the 5 models (0.100 s "
            "a hypothesis); canopy checks every model here, so the ranking saves nothing yet; with N models "
            "canopy (top-k = 5) would cost about N × 0.0100 s + 0.50 s a candidate against 0.50 s + (N − 5) "
            "× 0.100 s for verify over every model: at 100 models 1.5 s against 10.0 s, at 1 000 models "
            "10.5 s against 100.0 s") != std::string::npos);
  // The run with more hypotheses cheaper (noise in the times): no cost stated.
  const std::vector<report::SceneStageTime> odd = {cpu("gmatch", 10, 0.5, 0.5), cpu("verify", 10, 3.0, 3.0),
                                                   cpu("verify-ablation", 10, 5.0, 5.0)};
  CHECK(report::scene_markdown(score, odd, "scenes", nullptr, "", {}, {"--top-k=3", ablation.path, &all})
            .find(" Cost, the CPU") == std::string::npos);
  // An ablation that checked as many hypotheses as canopy (another option than top-k): its row, but
  // nothing in "What gmatch adds".
  verdict_of(5, "verdict-ablation.json");
  const std::string same_k = report::scene_markdown(score, times5, "scenes", nullptr, "", {},
                                                    {"--max-tilt=180", ablation.path, &all});
  CHECK(same_k.find("| all | all | 10 | verify `--max-tilt=180` (ablation) |") != std::string::npos);
  CHECK(same_k.find("What gmatch adds") == std::string::npos);
  verdict_of(3, "verdict.json");
  verdict_of(5, "verdict-ablation.json");

  // FPFH's poses scored by verify (mk/scenes.mk SCENE_FPFH_VERIFY: results/scenes/baseline-fpfh-verify/):
  // a row of its own, an ablation left out of the baseline goal, a clause of "What gmatch adds" (the
  // methods' order, the verify ablation's after it), its time per candidate: fitvox + the FPFH stage
  // + its verify.
  write(res / "baseline-fpfh-verify" / "score.json", score_text(res, run0, run1, 0.6, 0.7, 0.8, 3.0));
  std::vector<report::SceneStageTime> times_f = times;
  times_f.push_back(cpu("baseline-fpfh", 10, 6.0, 6.0));
  times_f.push_back(cpu("verify-fpfh", 10, 4.0, 4.0));
  const std::string mf = report::scene_markdown(score, times_f, "scenes", nullptr, "", {}, ablation);
  INFO(mf);
  CHECK(
      mf.find("| all | all | 10 | FPFH poses, verify (ablation) | 9 | 80.0% | 90.0% | 50.0% | 60.0% | 0.25 | "
              "3.0 |") != std::string::npos);
  CHECK(mf.find("| all | all | 10 | FPFH |") == std::string::npos);
  // the FPFH stage alone is a baseline only with its own score: still no "best baseline"
  CHECK(mf.find("best baseline") == std::string::npos);
  CHECK(mf.find(
            "What gmatch adds (issue 29): canopy's verify checks gmatch's top 3 of the 5 models; verify on "
            "the FPFH baseline's ranking and poses instead of gmatch's (its top-k of FPFH's list, each from "
            "FPFH's pose, its flip and the principal axes): recognition over all runs 60.0% against "
            "canopy's 80.0% (+20.0 points for canopy), precision 80.0% against 90.0%; verify again with "
            "`--top-k=1000`") != std::string::npos);
  // fitvox 0.2 + FPFH 0.6 + verify 0.4
  CHECK(mf.find("; FPFH poses, verify (ablation) 1.20 s (fitvox + 0.60 s FPFH + 0.40 s verify, 10 runs)") !=
        std::string::npos);
  fs::remove_all(res / "baseline-fpfh-verify");
  // Of other runs than canopy's: named, not shown.
  const documents::SceneScore other = documents::read_scene_score(
      score_text(res, run0, run0 + "x", 0.9, 1.0, 0.7, 2.0), "verify-ablation/score.json");
  const std::string md2 =
      report::scene_markdown(score, times, "scenes", nullptr, "", {},
                             {"--top-k=1000", (res / "verify-ablation" / "score.json").string(), &other});
  CHECK(md2.find("`--top-k=1000` (ablation)") == std::string::npos);
  CHECK(md2.find("verify-ablation/score.json scores other runs than canopy's") != std::string::npos);
  // Not run: no row, no sentence.
  const std::string md3 = report::scene_markdown(score, times, "scenes");
  CHECK(md3.find("What gmatch adds") == std::string::npos);
}

TEST_CASE("scene times: the baseline's per-candidate runs, only when it ran", "[report][baseline]") {
  const fs::path root = canopy::test::fresh_dir("report", "scene-baseline-times");
  const fs::path run = root / "light" / "tile-1" / "noise-0";
  write(run / "cands" / "c0001" / "baseline-fpfh.json.time", "0.75 40960\n");
  write(run / "cands" / "c0002" / "baseline-fpfh.json.time", "0.25 20480\n");
  auto t = report::scene_times({{run.string(), 0.09}});
  bool vfh = false, fpfh = false;
  for (const auto& s : t) {
    if (s.stage == "baseline-vfh") vfh = true;
    if (s.stage == "baseline-fpfh") {
      fpfh = true;
      CHECK(s.runs == 2);
      CHECK(s.seconds == Approx(1.0));
      CHECK(s.peak_mb == Approx(40));
    }
  }
  CHECK(fpfh);
  CHECK_FALSE(vfh);  // no baseline-vfh.json.time: not a row
}

TEST_CASE("baseline section: a table per scene too", "[report][baseline]") {
  const fs::path out = canopy::test::fresh_dir("report", "baseline-scenes") / "out";
  for (const std::string scene : {"circle", "flyby"}) {
    const fs::path dir = out / "sedan" / scene / "noise-0";
    fs::create_directories(dir);
    documents::MatchResult m;
    m.error_form = "bounded";
    documents::ModelScore s;
    s.model = "sedan";
    s.rank = 1;
    s.score = 0.8;
    m.models.push_back(s);
    documents::write_match_result(m, (dir / "match.json").string());
    const std::string fpfh = scene == "circle" ? "sedan" : "tank";
    std::ofstream(dir / "baseline.json")
        << R"({"format": "canopy.baseline", "version": 1, "methods": [)"
        << R"({"method": "vfh", "models": [{"rank": 1, "model": "tank"}]},)"
        << R"({"method": "fpfh", "models": [{"rank": 1, "model": ")" << fpfh << R"("}]}]})";
  }
  documents::ExperimentManifest manifest;
  manifest.objects = {"sedan"};
  manifest.scenes = {"circle", "flyby"};
  manifest.noises = {0};
  for (const std::string scene : {"circle", "flyby"})
    manifest.trials.push_back({"sedan", scene, 0, (out / "sedan" / scene / "noise-0").string()});
  const auto b = report::baseline_section(manifest);
  INFO(b.markdown);
  CHECK(b.markdown.find("| scene | trials | canopy (gmatch) | canopy (verify) | VFH | FPFH |") !=
        std::string::npos);
  CHECK(b.markdown.find("| circle | 1 | 1/1 = 100.0% [20.7, 100.0] | 0/1 = 0.0% [0.0, 79.3] | "
                        "0/1 = 0.0% [0.0, 79.3] | 1/1 = 100.0% [20.7, 100.0] |") != std::string::npos);
  CHECK(b.markdown.find("| flyby | 1 | 1/1 = 100.0% [20.7, 100.0] | 0/1 = 0.0% [0.0, 79.3] | "
                        "0/1 = 0.0% [0.0, 79.3] | 0/1 = 0.0% [0.0, 79.3] |") != std::string::npos);
}
