// The report's density ladder (issue 27): levels read from their scores, the runs' measured
// density and CPU, the level from which each capability meets its target, the table and CSV.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "canopy/documents/experiment_manifest.h"
#include "report/density_section.h"
#include "report/score_cells.h"
#include "support/cli.h"

using namespace canopy;
namespace fs = std::filesystem;

namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

// A summary row: cover, recall (any level) with an interval of ±0.1, class accuracy, heading
// median, false alarms per ha.
std::string row(const std::string& cover, double recall, double cls, double heading, double fa) {
  return R"({"cover": ")" + cover + R"(", "noise_mm": "all", "tiles": 2, "true": 10, "found_any_level": )" +
         num(recall * 10) + R"(, "tp": 0, "recall_any_level": )" + num(recall) +
         R"(, "recall_any_level_lo": )" + num(recall - 0.1) + R"(, "recall_any_level_hi": )" +
         num(recall + 0.05) + R"(, "class_accuracy_any_level": )" + num(cls) +
         R"(, "class_accuracy_any_level_lo": )" + num(cls - 0.1) +
         R"(, "class_accuracy_any_level_hi": 1, "heading_axis_error_any_level_median_deg": )" + num(heading) +
         R"(, "false_alarms_any_level_per_ha": )" + num(fa) + R"(, "false_alarms_any_level_per_ha_lo": 0,
         "false_alarms_any_level_per_ha_hi": )" +
         num(fa + 2) + "}";
}

// One level: a run directory with detect's index (its density) and two stage .time files (CPU
// 2 + 1 s and 0.5 + 0.5 s), a score naming the run (0.09 ha).
void level(const fs::path& root, const std::string& name, double all, double ground, const std::string& rows) {
  const fs::path run = root / "out" / name / "light" / "tile-1" / "noise-0";
  test::write_file(run / "cands" / "index.json",
                   R"({"format": "canopy.candidates", "version": 2, "tile": "scan.pcd", "margin": 0.5,
      "density": {"all": )" +
                       num(all) + R"(, "ground": )" + num(ground) + R"(, "first": null}, "candidates": []})");
  test::write_file(run / "detect.time", "4 1000 2 1\n");
  test::write_file(run / "cands.mk.time", "1 1000 0.5 0.5\n");
  // verify's ablation on a candidate (DENSITY_VERIFY_ABLATION): not canopy's cost, not in the CPU
  test::write_file(run / "cands" / "c0001" / "verdict-ablation.json.time", "7 1000 6 1\n");
  test::write_file(root / "res" / name / "score.json",
                   R"({"format": "canopy.scene_score", "version": 1, "params": {"match_radius_m": 1.5},
      "tiles": [{"detections": ")" +
                       (run / "detections.json").string() +
                       R"(", "truth": "t", "cover": "light", "noise_mm": 0, "area_ha": 0.09}],
      "summary": [)" + rows +
                       R"(], "pr": [], "models": [], "cover_bins": [],
      "matches": [{"tile": 0, "candidate": "c1", "x": 1, "y": 1, "outcome": "right", "instance": 1,
                   "true_model": "sedan"},
                  {"tile": 0, "candidate": null, "x": 5, "y": 5, "outcome": "missed", "instance": 2,
                   "true_model": "tank", "fate": "refused", "fate_candidate": "c2", "fate_reason": "too_sparse",
                   "fate_density": 2.5},
                  {"tile": 0, "candidate": "c3", "x": 9, "y": 9, "outcome": "false_alarm"}]})");
  test::write_file(run / "detections.json", R"({"format": "canopy.detections", "version": 2, "candidates": 4,
      "found": 2, "by_level": {"model": 0, "class": 2}, "by_reason": {"too_sparse": 1, "vegetation_like": 1},
      "density": null, "warning": null, "detections": [], "rejected": []})");
}

}  // namespace

TEST_CASE("density ladder: levels, measured density, CPU per ha and where each target is met") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "report-density";
  fs::remove_all(root);
  // Level 10: light recall 0.5; level 50: 0.95 (interval 0.85-1); level 100: 0.92 (0.82-0.97).
  // Class right 0.9 / 0.9 / 0.96 (the 10 level's all-cover row); heading 12 / 4 / 2 deg; false
  // alarms 3 / 0.5 / 0 per ha (upper bounds 5 / 2.5 / 2).
  level(root, "d10", 9.8, 7.9, row("light", 0.5, 0.9, 12, 3) + "," + row("all", 0.5, 0.9, 12, 3));
  level(root, "d50", 48, 39, row("light", 0.95, 0.9, 4, 0.5) + "," + row("all", 0.95, 0.9, 4, 0.5));
  level(root, "d100", 99, 80, row("light", 0.92, 0.96, 2, 0) + "," + row("all", 0.92, 0.96, 2, 0));
  std::vector<documents::ManifestDensity> m = {{10, 0.667, (root / "res/d10/score.json").string(), ""},
                                               {50, 0.298, (root / "res/d50/score.json").string(), ""},
                                               {100, 0.211, (root / "res/d100/score.json").string(), ""},
                                               {200, 0.149, (root / "res/d200/score.json").string(), ""}};
  const auto levels = report::read_density_levels(m);
  REQUIRE(levels.size() == 4);
  CHECK(levels[0].scored);
  CHECK_FALSE(levels[3].scored);  // not run: no score
  CHECK(levels[1].density_all == Approx(48));
  CHECK(levels[1].density_ground == Approx(39));
  CHECK(levels[1].density_runs == 1);
  CHECK(levels[1].cpu_seconds == Approx(4));  // detect 3 + plan 1 (not the verify ablation's 7)
  CHECK(levels[1].area_ha == Approx(0.09));
  CHECK(levels[1].by_reason.at("found") == 2);
  CHECK(levels[1].by_reason.at("too_sparse") == 1);
  CHECK(levels[1].model_found.at("sedan") == std::make_pair(1, 1));
  CHECK(levels[1].model_found.at("tank") == std::make_pair(0, 1));
  CHECK(levels[1].model_found.size() == 2);  // the false alarm names no model

  // A level that has not run ends the run of met levels from the top: nothing is "met from" a
  // level below a gap... except that the top level is missing, so every target is met nowhere.
  for (const auto& t : report::density_targets(levels)) CHECK(t.from_level == 0);
  const std::vector<report::DensityLevel> ran(levels.begin(), levels.begin() + 3);
  const auto targets = report::density_targets(ran);
  auto find = [&](const std::string& what) {
    for (const auto& t : targets)
      if (t.capability.find(what) != std::string::npos) return t;
    FAIL("no target " << what);
    return report::DensityTarget{};
  };
  // Recall, light: 0.95 and 0.92 meet 90%, 0.5 does not -> from 50; the lower bounds 0.85 and
  // 0.82 do not -> at no level.
  CHECK(find("light").from_level == 50);
  CHECK(find("light").from_level_bound == 0);
  CHECK(find("medium").from_level == 0);  // no medium row at any level
  // Class right: 0.9 / 0.9 / 0.96 all meet 85% -> from 10; bounds 0.8 / 0.8 / 0.86 -> from 100.
  CHECK(find("class right").from_level == 10);
  CHECK(find("class right").from_level_bound == 100);
  // Heading median <= 5: 4 and 2 -> from 50 (no interval: the same by the bound).
  CHECK(find("heading").from_level == 50);
  CHECK(find("heading").from_level_bound == 50);
  // False alarms <= 1/ha: 0.5 and 0 -> from 50; upper bounds 2.5 and 2 -> at no level.
  CHECK(find("false alarms").from_level == 50);
  CHECK(find("false alarms").from_level_bound == 0);

  const std::string md = report::density_markdown(levels, {"density/ladder-rates.png"});
  CHECK(md.find("## Density ladder") != std::string::npos);
  CHECK(md.find("| 200 | 0.149 | not run") != std::string::npos);
  CHECK(md.find("| 50 | 0.298 | 48 / 39 | light | 2 | 10 | ") != std::string::npos);
  CHECK(md.find("95.0% [85.0, 100.0]") != std::string::npos);
  CHECK(md.find("| 44 |") != std::string::npos);  // CPU 4 s / 0.09 ha on the all-cover row
  CHECK(md.find("![density ladder](density/ladder-rates.png)") != std::string::npos);
  CHECK(md.find("| model | 10 | 50 | 100 |") != std::string::npos);
  CHECK(md.find("| tank | 0/1 | 0/1 | 0/1 |") != std::string::npos);
  CHECK(md.find("| vegetation_like | 1 | 1 | 1 |") != std::string::npos);
  const std::string csv = report::density_csv(levels, "rates");
  CHECK(csv.rfind("level,spacing_m,density_all,density_ground,cover,metric,value,lo,hi\n", 0) == 0);
  CHECK(csv.find("50,0.298,48.0,39.0,light,recall_any_level,0.95,0.85,1\n") != std::string::npos);
  CHECK(csv.find("heading") == std::string::npos);
  CHECK(report::density_csv(levels, "errors").find("10,0.667,9.8,7.9,all,false_alarms_any_level_per_ha,3,0,5\n") !=
        std::string::npos);
}

TEST_CASE("density ladder: what the false alarms fell on, per level, from score's clutter table") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "report-density-clutter";
  fs::remove_all(root);
  level(root, "d10", 9.8, 7.9, row("all", 0.5, 0.9, 12, 3));
  level(root, "d50", 48, 39, row("all", 0.95, 0.9, 4, 0.5));
  auto levels = report::read_density_levels({{10, 0.667, (root / "res/d10/score.json").string(), ""},
                                             {50, 0.298, (root / "res/d50/score.json").string(), ""}});
  REQUIRE(levels.size() == 2);
  // No clutter table in the scores (written before it): no such table.
  CHECK(report::density_markdown(levels, {}).find("What the false alarms fell on") == std::string::npos);
  // Level 10: rock 2, a true vehicle 1, terrain 0 (and a light-cover row, not counted); level 50:
  // a caravan 1 and terrain 1, no rock row (no rock in its truths).
  auto clutter = [](const std::string& rows) {
    return documents::read_scene_score(
               R"({"format": "canopy.scene_score", "version": 1, "params": {"match_radius_m": 1.5}, "tiles": [],
        "summary": [], "pr": [], "models": [], "cover_bins": [], "matches": [], "clutter": [)" +
                   rows + "]}",
               "score.json")
        .clutter;
  };
  auto r = [](const char* cover, const char* kind, int fa) {
    return std::string(R"({"cover": ")") + cover + R"(", "kind": ")" + kind + R"(", "false_alarms": )" +
           std::to_string(fa) + "}";
  };
  levels[0].score.clutter = clutter(r("all", "rock", 2) + "," + r("all", "vehicle", 1) + "," +
                                    r("all", "none", 0) + "," + r("light", "rock", 5));
  levels[1].score.clutter = clutter(r("all", "caravan", 1) + "," + r("all", "none", 1));
  const std::string md = report::density_markdown(levels, {});
  const auto at = md.find("**What the false alarms fell on**");
  REQUIRE(at != std::string::npos);
  CHECK(at > md.find("**What became of the candidates**"));
  // Why the vehicles were missed: score's fate of each missed vehicle, per level.
  const auto why = md.find("**Why the vehicles were missed**");
  REQUIRE(why != std::string::npos);
  CHECK(why > md.find("**What became of the candidates**"));
  CHECK(why < at);
  CHECK(md.find("| fate | 10 | 50 |\n|---|---|---|\n| refused: too_sparse | 1 | 1 |\n", why) !=
        std::string::npos);
  CHECK(levels[0].missed_by_fate.at("refused: too_sparse") == 1);
  // The kinds in score's order across the levels: clutter kinds, then the vehicles, then none.
  const std::string table = md.substr(at);
  CHECK(table.find("| fell on | 10 | 50 |\n|---|---|---|\n"
                   "| rock (**unseen**) | 2 | – |\n"
                   "| caravan (**unseen**) | – | 1 |\n"
                   "| vehicle (a true vehicle, off its centre) | 1 | – |\n"
                   "| none (terrain, vegetation) | 0 | 1 |\n") != std::string::npos);
}

namespace {

// A summary row with the counts of the side-by-side table: class right and false alarms (fp
// model-level + class_fp class answers on no vehicle).
std::string row_counts(const std::string& cover, double recall, double cls, double fa, int right, int fp,
                       int class_fp) {
  std::string r = row(cover, recall, cls, 1, fa);
  r.pop_back();
  return r + R"(, "class_right_any_level": )" + std::to_string(right) + R"(, "fp": )" + std::to_string(fp) +
         R"(, "class_fp": )" + std::to_string(class_fp) + "}";
}

// An "all" row with model-level answers: `detections` of them, `identified` right (interval
// ±0.1 around the share), and the found / class right / false alarms of row_counts.
std::string model_rows(double recall, int detections, int identified, int fp) {
  std::string r = row_counts("all", recall, 0.9, 1, 8, fp, 0);
  r.pop_back();
  const double share = detections > 0 ? static_cast<double>(identified) / detections : 0;
  return r + R"(, "detections": )" + std::to_string(detections) + R"(, "identified": )" +
         std::to_string(identified) + R"(, "identification": )" + num(share) + R"(, "identification_lo": )" +
         num(share - 0.1) + R"(, "identification_hi": 1})";
}

// Light, medium and all rows of one level (all: the mean of light's and medium's recall).
std::string rows(double light, double medium, double cls, double fa, int right, int fp, int cfp) {
  return row_counts("light", light, cls, fa, right, fp, cfp) + "," +
         row_counts("medium", medium, cls, fa, right, fp, cfp) + "," +
         row_counts("all", (light + medium) / 2, cls, fa, right, fp, cfp);
}

// A sensor tile's truth.json beside the level's run (rangetrace's measured density).
void sensor_truth(const fs::path& root, const std::string& name, double pulses, double returns) {
  test::write_file(root / "out" / name / "light" / "tile-1" / "truth.json",
                   R"({"format": "canopy.scene_truth", "version": 1, "vehicles": [],
      "density": {"returns_per_m2": )" +
                       num(returns) + R"(, "first_returns_per_m2": 1, "pulses_per_m2": )" + num(pulses) +
                       R"(, "pulses_by_returns": [0, 1]}})");
}

}  // namespace

TEST_CASE(
    "density ladder on the sensor: measured pulses and returns, its targets, the two ladders side by side") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "report-density-sensor";
  fs::remove_all(root);
  // Pixel ladder 10 and 25; sensor ladder 10, 25 and 50 (als_qL1).
  level(root, "d10", 10, 6, rows(0.6, 0.3, 0.9, 2, 4, 0, 2));
  level(root, "d25", 25, 16, rows(0.8, 0.6, 0.9, 1, 6, 0, 1));
  level(root, "s10", 12, 9, rows(0.5, 0.2, 0.8, 3, 3, 1, 2));
  level(root, "s25", 28, 20, rows(0.9, 0.7, 0.95, 0.5, 8, 0, 1));
  level(root, "s50", 55, 40, rows(0.95, 0.8, 0.95, 0, 9, 0, 0));
  sensor_truth(root, "s10", 10.2, 12.9);
  sensor_truth(root, "s25", 24.8, 31.4);
  // s50: an image-mode truth (no density): the measured density is unknown.
  test::write_file(root / "out" / "s50" / "light" / "tile-1" / "truth.json",
                   R"({"format": "canopy.scene_truth", "version": 1, "vehicles": []})");
  const std::vector<documents::ManifestDensity> pixel = {
      {10, 0.667, (root / "res/d10/score.json").string(), ""},
      {25, 0.422, (root / "res/d25/score.json").string(), ""}};
  std::vector<documents::ManifestDensity> sm;
  for (const char* l : {"10", "25", "50"})
    sm.push_back(
        {std::stod(l), 0, (root / "res" / (std::string("s") + l) / "score.json").string(), "als_qL1"});
  const auto levels = report::read_density_levels(pixel);
  const auto sensor = report::read_density_levels(sm);
  REQUIRE(sensor.size() == 3);
  CHECK(levels[0].pulses == -1);  // the pixel ladder reads no truth
  CHECK(sensor[0].sensor == "als_qL1");
  CHECK(sensor[0].pulses == Approx(10.2));
  CHECK(sensor[1].returns == Approx(31.4));
  CHECK(sensor[2].pulses == -1);
  CHECK(sensor[2].scored);

  // Where each capability begins on the sensor: light recall 0.9 from 25, medium 0.75 at 50 only.
  auto find = [](const std::vector<report::DensityTarget>& ts, const std::string& what) {
    for (const auto& t : ts)
      if (t.capability.find(what) != std::string::npos) return t;
    FAIL("no target " << what);
    return report::DensityTarget{};
  };
  const auto targets = report::density_targets(sensor);
  CHECK(find(targets, "light").from_level == 25);
  CHECK(find(targets, "medium").from_level == 50);
  CHECK(find(targets, "false alarms").from_level == 25);

  const std::string md = report::density_markdown(levels, {}, sensor);
  CHECK(md.find("### The ladder on the realistic sensor (als_qL1)") != std::string::npos);
  CHECK(md.find("| level (pulses/m²) | measured pulses / returns (per m²) |") != std::string::npos);
  CHECK(md.find("| 25 | 24.8 / 31.4 | 28 / 20 | light | 2 | 10 | 9/10 (0/9 model) | 90.0% [80.0, 95.0] |") !=
        std::string::npos);
  CHECK(md.find("| 50 | – | 55 / 40 | light |") != std::string::npos);
  CHECK(md.find("| vehicles detected, light cover | >= 90% | 25 pulses/m² | at no level |") !=
        std::string::npos);
  CHECK(md.find("| vehicles detected, light cover | >= 90% | at no level | at no level |") !=
        std::string::npos);  // the pixel ladder's
  // Side by side at 10 and 25 (the sensor's 50 has no pixel level): counts and intervals.
  CHECK(md.find("| level | measure | pixel spacing | sensor (als_qL1) |") != std::string::npos);
  CHECK(md.find("| 25 | recall, light | 8/10 = 80.0% [70.0, 85.0] | 9/10 = 90.0% [80.0, 95.0] |") !=
        std::string::npos);
  CHECK(md.find("| 10 | recall, medium | 3/10 = 30.0% [20.0, 35.0] | 2/10 = 20.0% [10.0, 25.0] |") !=
        std::string::npos);
  CHECK(md.find("| 25 | class right (all) | 6/7 = 90.0% [80.0, 100.0] | 8/8 = 95.0% [85.0, 100.0] |") !=
        std::string::npos);
  CHECK(md.find("| 10 | false alarms/ha (all) | 2 = 2.0 [0.0, 4.0] | 3 = 3.0 [0.0, 5.0] |") !=
        std::string::npos);
  CHECK(md.find("| 50 | recall") == std::string::npos);
  // No level has classify's ablation: no ablation table.
  CHECK(md.find("classify's ablation") == std::string::npos);

  // classify's ablation on 25 (scored) and 50 (named, not run): a table for 25 alone, canopy beside
  // the ablation per cover, class right and false alarms with their counts.
  level(root, "a25", 28, 20, rows(0.7, 0.4, 0.9, 2.5, 7, 1, 1));
  sm[1].classify.change = "bench/density/classify-sim-late-0.35.ini";
  sm[1].classify.score = (root / "res/a25/score.json").string();
  sm[2].classify.change = sm[1].classify.change;
  sm[2].classify.score = (root / "res/a50/score.json").string();  // not run
  const auto with = report::read_density_levels(sm);
  CHECK(!with[0].classify.scored);
  CHECK(with[1].classify.scored);
  CHECK(!with[2].classify.scored);
  const std::string ma = report::density_markdown(levels, {}, with);
  CHECK(ma.find("**classify's ablation on the sensor ladder** (the same candidates classified with "
                "`bench/density/classify-sim-late-0.35.ini`") != std::string::npos);
  CHECK(ma.find("| 25 | recall, light | 9/10 = 90.0% [80.0, 95.0] | 7/10 = 70.0% [60.0, 75.0] |") !=
        std::string::npos);
  CHECK(ma.find("| 25 | recall, medium | 7/10 = 70.0% [60.0, 75.0] | 4/10 = 40.0% [30.0, 45.0] |") !=
        std::string::npos);
  CHECK(ma.find("| 25 | false alarms/ha (all) | 1 = 0.5 [0.0, 2.5] | 2 = 2.5 [0.0, 4.5] |") !=
        std::string::npos);
  CHECK(ma.find("| 25 | recall, dense") == std::string::npos);  // no dense row in either score
  CHECK(ma.find("| 50 | recall, light | 9") == std::string::npos);
  CHECK(ma.find("| 10 | recall, light | 5") == std::string::npos);
  // Without sensor levels the section is the pixel ladder's alone.
  CHECK(report::density_markdown(levels, {}).find("realistic sensor") == std::string::npos);
}

TEST_CASE("density ladder: verify's ablation beside canopy on the rungs with a model-level answer") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "report-density-verify";
  fs::remove_all(root);
  // Pixel 25: no model answer in either (left out); pixel 100: 9 answers -> 11 with the rule;
  // sensor 50: 2 of 3 right with the rule, 1 of 1 in the ablation.
  level(root, "d25", 25, 16, model_rows(0.7, 0, 0, 0));
  level(root, "v25", 25, 16, model_rows(0.7, 0, 0, 0));
  level(root, "d100", 99, 80, model_rows(0.9, 11, 11, 0));
  level(root, "v100", 99, 80, model_rows(0.9, 9, 9, 0));
  level(root, "s50", 55, 40, model_rows(0.8, 3, 2, 1));
  level(root, "w50", 55, 40, model_rows(0.7, 1, 1, 0));
  std::vector<documents::ManifestDensity> pixel = {{25, 0.422, (root / "res/d25/score.json").string(), ""},
                                                   {100, 0.211, (root / "res/d100/score.json").string(), ""},
                                                   {200, 0.149, (root / "res/d200/score.json").string(), ""}};
  std::vector<documents::ManifestDensity> sensor = {
      {50, 0, (root / "res/s50/score.json").string(), "als_qL1"}};
  // Without the ablation's records: no table.
  CHECK(report::density_markdown(report::read_density_levels(pixel), {}, report::read_density_levels(sensor))
            .find("verify's ablation") == std::string::npos);
  pixel[0].verify.change = pixel[1].verify.change = pixel[2].verify.change = "--seen-spacing=0";
  pixel[0].verify.score = (root / "res/v25/score.json").string();
  pixel[1].verify.score = (root / "res/v100/score.json").string();
  pixel[2].verify.score = (root / "res/v200/score.json").string();  // not run
  sensor[0].verify.change = "--seen-spacing=0";
  sensor[0].verify.score = (root / "res/w50/score.json").string();
  const auto levels = report::read_density_levels(pixel);
  const auto sens = report::read_density_levels(sensor);
  CHECK(levels[0].verify.scored);
  CHECK(levels[1].verify.scored);
  CHECK(!levels[2].verify.scored);
  CHECK(levels[1].verify.change == "--seen-spacing=0");
  const std::string md = report::density_markdown(levels, {}, sens);
  CHECK(md.find("**verify's ablation on the density ladder** (the same model-level candidates verified again "
                "with `--seen-spacing=0`") != std::string::npos);
  CHECK(md.find(
            "| pixel | 100 | model answers, identified | 11/11 = 100.0% [90.0, 100.0] | 9/9 = 100.0% [90.0, "
            "100.0] |") != std::string::npos);
  CHECK(md.find(
            "| pixel | 100 | found (all covers) | 9/10 = 90.0% [80.0, 95.0] | 9/10 = 90.0% [80.0, 95.0] |") !=
        std::string::npos);
  CHECK(
      md.find("| als_qL1 | 50 | model answers, identified | 2/3 = 66.7% [56.7, 100.0] | 1/1 = 100.0% [90.0, "
              "100.0] |") != std::string::npos);
  CHECK(
      md.find(
          "| als_qL1 | 50 | found (all covers) | 8/10 = 80.0% [70.0, 85.0] | 7/10 = 70.0% [60.0, 75.0] |") !=
      std::string::npos);
  CHECK(md.find("| als_qL1 | 50 | false alarms/ha (all) | 1 = 1.0 [0.0, 3.0] | 0 = 1.0 [0.0, 3.0] |") !=
        std::string::npos);
  CHECK(md.find("| pixel | 25 |") == std::string::npos);   // no model answer in either
  CHECK(md.find("| pixel | 200 |") == std::string::npos);  // not run
  CHECK(md.find("classify's ablation") == std::string::npos);

  // classify's ablation on a pixel rung (the density record's ablation): its own table.
  pixel[1].classify.change = "bench/density/classify-sim-floor-100.ini";
  pixel[1].classify.score = (root / "res/s50/score.json").string();
  const std::string mc = report::density_markdown(report::read_density_levels(pixel), {}, sens);
  CHECK(mc.find("**classify's ablation on the density ladder** (the same candidates classified with "
                "`bench/density/classify-sim-floor-100.ini`") != std::string::npos);
  CHECK(mc.find("| 100 | class right (all) | 8/9 = 90.0% [80.0, 100.0] | 8/8 = 90.0% [80.0, 100.0] |") !=
        std::string::npos);
  // The wrong class of the found: found - class right, 1 - class right's rate, its interval turned
  // over (score_cells.h class_ablation_table, shared with the scene experiment's).
  CHECK(mc.find("| 100 | wrong class (all) | 1/9 = 10.0% [0.0, 20.0] | 0/8 = 10.0% [0.0, 20.0] |") !=
        std::string::npos);
  CHECK(mc.find("classify's ablation on the sensor ladder") == std::string::npos);
  CHECK(mc.find("classify's second ablation") == std::string::npos);

  // classify's second ablation on the same rung (density-classify): a table of its own, after the
  // first's, with its own file and numbers; the first's table unchanged.
  pixel[1].classify_more = {
      {"bench/density/classify-sim-shoulder-0.ini", (root / "res/s50/score.json").string()}};
  // not run: no row
  pixel[0].classify_more = {
      {"bench/density/classify-sim-shoulder-0.ini", (root / "res/missing/score.json").string()}};
  const std::vector<report::DensityLevel> l2 = report::read_density_levels(pixel);
  CHECK(l2[1].classify_more.at(0).scored);
  CHECK(!l2[0].classify_more.at(0).scored);
  const std::string m2 = report::density_markdown(l2, {}, sens);
  const auto first = m2.find("**classify's ablation on the density ladder**");
  const auto second = m2.find(
      "**classify's second ablation on the density ladder** (the same candidates "
      "classified with `bench/density/classify-sim-shoulder-0.ini`");
  REQUIRE(first != std::string::npos);
  REQUIRE(second != std::string::npos);
  CHECK(first < second);
  const std::string tail = m2.substr(second);
  CHECK(tail.find("| 100 | class right (all) | 8/9 = 90.0% [80.0, 100.0] | 8/8 = 90.0% [80.0, 100.0] |") !=
        std::string::npos);
  CHECK(tail.find("| 25 |") == std::string::npos);
  CHECK(m2.substr(0, second) == mc.substr(0, second));
  CHECK(m2.find("classify's third ablation") == std::string::npos);

  // A third ablation on the same rung (a second density-classify record): its own table after the
  // second's, the tables before it unchanged.
  pixel[1].classify_more.push_back(
      {"bench/density/classify-sim-sampled-0.ini", (root / "res/s50/score.json").string()});
  const std::vector<report::DensityLevel> l3 = report::read_density_levels(pixel);
  REQUIRE(l3[1].classify_more.size() == 2);
  CHECK(l3[1].classify_more[1].scored);
  const std::string m3 = report::density_markdown(l3, {}, sens);
  const auto third = m3.find(
      "**classify's third ablation on the density ladder** (the same candidates classified with "
      "`bench/density/classify-sim-sampled-0.ini`");
  REQUIRE(third != std::string::npos);
  CHECK(third > m3.find("**classify's second ablation on the density ladder**"));
  CHECK(m3.substr(0, third) == m2.substr(0, third));
  CHECK(m3.find("classify's fourth ablation") == std::string::npos);

  // A fourth (a third density-classify record): its own table after the third's.
  pixel[1].classify_more.push_back(
      {"bench/density/classify-sim-rim-0.ini", (root / "res/s50/score.json").string()});
  const std::vector<report::DensityLevel> l4 = report::read_density_levels(pixel);
  REQUIRE(l4[1].classify_more.size() == 3);
  const std::string m4 = report::density_markdown(l4, {}, sens);
  const auto fourth = m4.find(
      "**classify's fourth ablation on the density ladder** (the same candidates classified with "
      "`bench/density/classify-sim-rim-0.ini`");
  REQUIRE(fourth != std::string::npos);
  CHECK(fourth > m4.find("**classify's third ablation on the density ladder**"));
  CHECK(m4.substr(0, fourth) == m3.substr(0, fourth));
}

TEST_CASE("density ladder: detect's ablations on the class-level rungs, one table each, after classify's") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "report-density-detect";
  fs::remove_all(root);
  // canopy (end-gap 1) at 10, 25 and 100; detect's ablation (end-gap 0) on 10 and 25 only (the
  // class-level rungs): 10 finds one light vehicle fewer, 25 two, each with a false alarm more.
  level(root, "d10", 10, 6, rows(0.6, 0.3, 0.9, 2, 4, 0, 2));
  level(root, "d25", 25, 16, rows(0.8, 0.6, 0.9, 1, 6, 0, 1));
  level(root, "d100", 99, 80, rows(0.9, 0.8, 0.95, 0, 9, 0, 0));
  level(root, "e10", 10, 6, rows(0.5, 0.3, 0.9, 3, 4, 0, 3));
  level(root, "e25", 25, 16, rows(0.6, 0.6, 0.9, 2, 5, 0, 2));
  level(root, "c25", 25, 16, rows(0.7, 0.6, 0.9, 1, 5, 0, 1));
  level(root, "s25", 28, 20, rows(0.9, 0.7, 0.95, 0.5, 8, 0, 1));
  level(root, "f25", 28, 20, rows(0.8, 0.7, 0.95, 1.5, 7, 1, 1));
  std::vector<documents::ManifestDensity> pixel = {{10, 0.667, (root / "res/d10/score.json").string(), ""},
                                                   {25, 0.422, (root / "res/d25/score.json").string(), ""},
                                                   {100, 0.211, (root / "res/d100/score.json").string(), ""}};
  std::vector<documents::ManifestDensity> sensor = {
      {25, 0, (root / "res/s25/score.json").string(), "als_qL1"}};
  // Without density-detect records: no detect table.
  CHECK(report::density_markdown(report::read_density_levels(pixel), {}, report::read_density_levels(sensor))
            .find("ablation on the density ladder** (the rung's whole chain") == std::string::npos);
  const std::string eg0 = "bench/density/detect-end-gap-0.ini";
  pixel[0].detect = {{eg0, (root / "res/e10/score.json").string()}};
  pixel[1].detect = {{eg0, (root / "res/e25/score.json").string()}};
  pixel[1].classify = {"bench/density/classify-sim-floor-100.ini", (root / "res/c25/score.json").string()};
  sensor[0].detect = {{eg0, (root / "res/f25/score.json").string()}};
  const auto levels = report::read_density_levels(pixel);
  const auto sens = report::read_density_levels(sensor);
  REQUIRE(levels[0].detect.size() == 1);
  CHECK(levels[0].detect[0].scored);
  CHECK(levels[0].detect[0].change == eg0);
  CHECK(levels[2].detect.empty());
  const std::string md = report::density_markdown(levels, {}, sens);
  const auto head = md.find(
      "**detect's ablation on the density ladder** (the rung's whole chain run again — detect with `" + eg0 +
      "`");
  REQUIRE(head != std::string::npos);
  // After classify's table, before the sensor ladder's part.
  CHECK(md.find("**classify's ablation on the density ladder**") < head);
  const auto sensor_part = md.find("### The ladder on the realistic sensor");
  REQUIRE(sensor_part != std::string::npos);
  CHECK(head < sensor_part);
  const std::string table = md.substr(head, sensor_part - head);
  CHECK(table.find("| 10 | recall, light | 6/10 = 60.0% [50.0, 65.0] | 5/10 = 50.0% [40.0, 55.0] |") !=
        std::string::npos);
  CHECK(table.find("| 25 | recall, light | 8/10 = 80.0% [70.0, 85.0] | 6/10 = 60.0% [50.0, 65.0] |") !=
        std::string::npos);
  CHECK(table.find("| 25 | recall, medium | 6/10 = 60.0% [50.0, 65.0] | 6/10 = 60.0% [50.0, 65.0] |") !=
        std::string::npos);
  CHECK(table.find("| 10 | false alarms/ha (all) | 2 = 2.0 [0.0, 4.0] | 3 = 3.0 [0.0, 5.0] |") !=
        std::string::npos);
  CHECK(table.find("| 25 | class right (all) | 6/7 = 90.0% [80.0, 100.0] | 5/6 = 90.0% [80.0, 100.0] |") !=
        std::string::npos);
  CHECK(table.find("| 100 |") == std::string::npos);  // a model-level rung: no detect ablation
  CHECK(
      md.find("**detect's ablation on the sensor ladder** (the rung's whole chain run again — detect with `" +
              eg0 + "`") > sensor_part);
  CHECK(md.find("| 25 | false alarms/ha (all) | 1 = 0.5 [0.0, 2.5] | 2 = 1.5 [0.0, 3.5] |", sensor_part) !=
        std::string::npos);
  CHECK(md.find("detect's second ablation") == std::string::npos);

  // A second entry (density-detect's second record) on 25 alone, and one named but not run on 10:
  // its own table after the first's, with 25's row only; the first table unchanged.
  pixel[1].detect.push_back({"bench/density/detect-other.ini", (root / "res/e10/score.json").string()});
  pixel[0].detect.push_back({"bench/density/detect-other.ini", (root / "res/missing/score.json").string()});
  const auto l2 = report::read_density_levels(pixel);
  CHECK(!l2[0].detect[1].scored);
  const std::string m2 = report::density_markdown(l2, {}, sens);
  const auto second = m2.find(
      "**detect's second ablation on the density ladder** (the rung's whole chain run again — "
      "detect with `bench/density/detect-other.ini`");
  REQUIRE(second != std::string::npos);
  CHECK(m2.find("**detect's ablation on the density ladder**") < second);
  const std::string t2 = m2.substr(second, m2.find("### The ladder on the realistic sensor") - second);
  CHECK(t2.find("| 25 | recall, light | 8/10 = 80.0% [70.0, 85.0] | 5/10 = 50.0% [40.0, 55.0] |") !=
        std::string::npos);
  CHECK(t2.find("| 10 |") == std::string::npos);
  CHECK(m2.substr(0, second) == md.substr(0, second));
}

TEST_CASE("density ladder: the model level's ablation, its own table among detect's") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "report-density-model";
  fs::remove_all(root);
  // canopy (model level 20) at 25 and 50: 2 and 6 model answers, all right; the ablation (50):
  // none at 25, 1 at 50; found the same; detect's ablation (end-gap 0) on both as well.
  level(root, "d25", 25, 16, model_rows(0.8, 2, 2, 1));
  level(root, "d50", 50, 35, model_rows(0.9, 6, 6, 0));
  level(root, "m25", 25, 16, model_rows(0.8, 0, 0, 1));
  level(root, "m50", 50, 35, model_rows(0.9, 1, 1, 0));
  level(root, "e25", 25, 16, model_rows(0.7, 2, 2, 2));
  level(root, "e50", 50, 35, model_rows(0.8, 6, 6, 1));
  std::vector<documents::ManifestDensity> pixel = {{25, 0.422, (root / "res/d25/score.json").string(), ""},
                                                   {50, 0.298, (root / "res/d50/score.json").string(), ""}};
  const std::string eg0 = "bench/density/detect-end-gap-0.ini", m50 = "TILE_MODEL_DENSITY=50";
  pixel[0].detect = {{eg0, (root / "res/e25/score.json").string()},
                     {m50, (root / "res/m25/score.json").string()}};
  pixel[1].detect = {{eg0, (root / "res/e50/score.json").string()},
                     {m50, (root / "res/m50/score.json").string()}};
  const std::string md = report::density_markdown(report::read_density_levels(pixel), {});
  INFO(md);
  const auto detect =
      md.find("**detect's ablation on the density ladder** (the rung's whole chain run again");
  const auto model = md.find(
      "**the model level's ablation on the density ladder** (the rung's whole chain run again with `" + m50 +
      "`");
  REQUIRE(detect != std::string::npos);
  REQUIRE(model != std::string::npos);
  CHECK(detect < model);
  // detect's table is still "the" ablation (the model level's is not counted among detect's), and
  // the model entry has no classify-style table of its own.
  CHECK(md.find("detect's second ablation") == std::string::npos);
  CHECK(md.find("with `" + m50 + "`, then classify") == std::string::npos);
  const std::string table = md.substr(model);
  CHECK(table.find("| 25 | model answers, identified | 2/2 = 100.0% [90.0, 100.0] | 0/0") != std::string::npos);
  CHECK(table.find("| 50 | model answers, identified | 6/6 = 100.0% [90.0, 100.0] | 1/1 = 100.0% [90.0, "
                   "100.0] |") != std::string::npos);
  CHECK(table.find("| 50 | found (all covers) | ") != std::string::npos);
  CHECK(table.find("| 25 | false alarms/ha (all) | 1 = ") != std::string::npos);
}

TEST_CASE("an ablation's name by its place: the density ladder's, the real tiles' and the scenes' one word") {
  CHECK(report::ablation_name(1) == "ablation");
  CHECK(report::ablation_name(0) == "ablation");
  CHECK(report::ablation_name(2) == "second ablation");
  CHECK(report::ablation_name(4) == "fourth ablation");
  CHECK(report::ablation_name(6) == "sixth ablation");
  CHECK(report::ablation_name(7) == "ablation 7");
}
