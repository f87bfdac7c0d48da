// The report's "Real tiles" section on hand-made out/real trees: a labelled tile with known
// matches (recall 8/10 and 6/8 clear, a false alarm on an uncertain object left out of
// precision 8/9, class 7/8: Wilson intervals; the two clear vehicles missed, one refused, one
// without a candidate), plots without vehicles (2 false alarms on 0.25 ha: exact Poisson
// interval), a v1 detections document, a tile stopped by its time box and one not run; a document that does
// not add up is refused naming its file.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "report/real_section.h"
#include "support/cli.h"

using namespace canopy;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) { test::write_file(p, text); }

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string detection(const std::string& id, const std::string& cls, const std::string& group) {
  return R"({"candidate": ")" + id + R"(", "level": "class", "model": null, "class": ")" + cls +
         R"(", "group": ")" + group +
         R"(", "confidence": 0.8, "pose": {"x": 0, "y": 0, "z": 0, "heading": 0}})";
}

// townA: 10 labelled vehicles (1-8 clear, 9-10 partial), one uncertain object at (500, 500);
// 10 detections: 8 matched (instances 1-6, 9, 10; c08 answered van on a car), c09 a false
// alarm 0.54 m from the uncertain object, c10 one far from everything.
void town(const fs::path& root, const fs::path& labels) {
  std::string vehicles;
  for (int i = 1; i <= 10; ++i) {
    vehicles += std::string(i > 1 ? ", " : "") + R"({"instance": )" + std::to_string(i) +
                R"(, "model": "car", "pose": {"x": )" + std::to_string(10 * i) +
                R"(, "y": 0, "z": 0, "heading": 0}, "canopy_cover": 0, "visibility": ")" +
                (i <= 8 ? "clear" : "partial") + "\"}";
  }
  write(labels / "townA.truth.json",
        R"({"format": "canopy.scene_truth", "version": 1, "extent": [100, 50], "origin": [0, 0], "vehicles": [)" +
            vehicles + R"(], "uncertain": [{"id": "u1", "pose": {"x": 500, "y": 500, "heading": 0}}]})");
  std::string dets;
  for (int i = 1; i <= 10; ++i) {
    const std::string id = "c0" + std::to_string(i);
    dets +=
        std::string(i > 1 ? ", " : "") + detection(id, i == 8 ? "van" : "hatchback", i == 8 ? "van" : "car");
  }
  const fs::path d = root / "townA";
  write(d / "detections.json", R"({"format": "canopy.detections", "version": 2, "candidates": 14, "found": 10,
    "by_level": {"model": 0, "class": 10}, "by_reason": {"too_sparse": 3, "none": 1},
    "density": {"all": 15.5, "ground": 12.0, "first": 11.0}, "warning": null, "detections": [)" +
                                   dets + R"(], "rejected": []})");
  write(d / "cands" / "index.json", R"({"format": "canopy.candidates", "version": 1, "tile": "townA.laz",
    "tile_points": 77500, "ground": {"cell": 0.5, "cells": 20000}, "candidates": []})");
  std::string rows;
  const int instance[] = {1, 2, 3, 4, 5, 6, 9, 10};
  for (int i = 0; i < 8; ++i) {
    rows += R"({"tile": 0, "candidate": "c0)" + std::to_string(i + 1) + R"(", "x": 0, "y": 0, "outcome": ")" +
            (i == 7 ? "wrong" : "right") + R"(", "instance": )" + std::to_string(instance[i]) +
            R"(, "true_model": "car"}, )";
  }
  rows += R"({"tile": 0, "candidate": "c09", "x": 500.5, "y": 500.2, "outcome": "false_alarm"},
             {"tile": 0, "candidate": "c010", "x": 600, "y": 600, "outcome": "false_alarm"},
             {"tile": 0, "candidate": null, "x": 70, "y": 0, "outcome": "missed", "instance": 7,
              "fate": "refused", "fate_candidate": "c12", "fate_reason": "vegetation_like", "fate_density": 14},
             {"tile": 0, "candidate": null, "x": 80, "y": 0, "outcome": "missed", "instance": 8,
              "fate": "no_candidate"})";
  write(d / "score.json", R"({"format": "canopy.scene_score", "version": 1, "params": {"match_radius_m": 1.5},
    "tiles": [{"detections": "d", "truth": "t", "area_ha": 0.5, "true": 10, "tp": 8, "fp": 2, "fn": 2}],
    "matches": [)" + rows + "]}");
  write(d / "tile.time", "42.5 300000 50.25 2.5\n");
  write(d / "detect.time", "10 200000 9.5 0.5\n");
  write(d / "cands" / "c01" / "class.json.time", "0.5 1000 0.25 0.25\n");
}

// plotA (v2): 2 class-level detections on 0.25 ha (detect's grid: 10 000 cells of 0.5 m), no
// density in the index (measured: 59 712 points / 2 500 m²); plotB (v1): 0 found, 3 none and
// 4 failed, 0.25 ha, 8 points per m² (measured: under the forest table's dense band of 10).
void plots(const fs::path& root) {
  write(root / "plotA" / "detections.json", R"({"format": "canopy.detections", "version": 2, "candidates": 10,
    "found": 2, "by_level": {"model": 0, "class": 2},
    "by_reason": {"too_sparse": 5, "vegetation_like": 2, "failed": 1}, "density": null,
    "warning": "most candidates are too sparse", "detections": [)" +
                                                detection("c1", "hatchback", "car") + ", " +
                                                detection("c2", "van", "van") + R"(], "rejected": []})");
  write(root / "plotA" / "cands" / "index.json", R"({"format": "canopy.candidates", "version": 1,
    "tile": "plotA.laz", "tile_points": 59712, "ground": {"cell": 0.5, "cells": 10000}, "candidates": []})");
  write(root / "plotA" / "tile.time", "20.5 100000 30.2 1.3\n");
  write(root / "plotB" / "detections.json", R"({"format": "canopy.detections", "version": 1, "candidates": 7,
    "found": 0, "none": 3, "failed": 4, "detections": [], "rejected": []})");
  write(root / "plotB" / "cands" / "index.json", R"({"format": "canopy.candidates", "version": 1,
    "tile": "plotB.laz", "tile_points": 20000, "ground": {"cell": 0.5, "cells": 10000}, "candidates": []})");
  write(root / "plotB" / "tile.time", "75 100000 70 2\n");
}

}  // namespace

TEST_CASE("real tiles: a labelled tile's recall, precision and class with Wilson intervals") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "report-real" / "town";
  fs::remove_all(root);
  const fs::path labels = root / "labels", out = root / "real";
  town(out, labels);
  const report::RealTile t =
      report::read_real_tile({"townA", (out / "townA").string(), (labels / "townA.truth.json").string()});
  CHECK(t.ran);
  CHECK(t.finished);
  CHECK(t.scored);
  CHECK(t.version == 2);
  CHECK(t.candidates == 14);
  CHECK(t.found == 10);
  CHECK(t.by_level.at("class") == 10);
  CHECK(t.by_class.at("class: hatchback") == 9);
  CHECK(t.by_class.at("class: van") == 1);
  CHECK(t.by_reason.at("too_sparse") == 3);
  CHECK(t.vehicles == 10);
  CHECK(t.clear == 8);
  CHECK(t.uncertain == 1);
  CHECK(t.recall_all.k == 8);
  CHECK(t.recall_all.n == 10);
  CHECK(t.recall_clear.k == 6);
  CHECK(t.recall_clear.n == 8);
  CHECK(t.tp == 8);
  CHECK(t.fp == 2);
  CHECK(t.fp_on_uncertain == 1);
  CHECK(t.precision.k == 8);
  CHECK(t.precision.n == 9);
  CHECK(t.class_right.k == 7);
  CHECK(t.class_right.n == 8);
  CHECK(t.area_ha == 0.5);   // score's, from the labels' extent
  CHECK(t.density == 15.5);  // the detections' density.all
  CHECK(t.density_from == "index");
  CHECK(t.points == 77500);
  CHECK(t.time.seconds == 42.5);
  CHECK(t.time.cpu_seconds() == Approx(52.75));
  CHECK(t.stage_runs == 2);  // detect and the candidate's stage; tile.time is the run's own
  CHECK(t.stages_cpu == Approx(10.5));

  const std::string md = report::real_markdown({t}, 180);
  INFO(md);
  CHECK(has(md, "## Real tiles"));
  CHECK(has(md,
            "| townA | 10 (8) | 1 | 10 | 8 | 2 (1) | 8/10 = 80.0% [49.0, 94.3] | 6/8 = 75.0% [40.9, 92.9] | "
            "8/9 = 88.9% [56.5, 98.0] | 7/8 = 87.5% [52.9, 97.8] |"));
  CHECK(has(md,
            "| townA | – | 0.50 | 15.5 | 77500 | 14 | 10 (0 / 10) | class: hatchback 9, class: van 1 | "
            "none 1, too_sparse 3 | – |"));
  CHECK(has(md, "| townA | 42.5 | 52.8 | 10.5 (2) | yes |"));
  // Where the two missed (clear) vehicles were lost: score's fates, per tile and over all.
  CHECK(t.lost_clear.at("refused: vegetation_like") == 1);
  CHECK(t.lost_all.at("no candidate") == 1);
  CHECK(has(md, "| fate | townA | all scored |"));
  CHECK(has(md,
            "| no candidate | 1 (1) | 1 (1) |\n| refused: vegetation_like | 1 (1) | 1 (1) |\n| **lost** | 2 "
            "(2) | 2 (2) |"));
  CHECK(has(md, "median 14.0, quartiles 14.0–14.0, range 14.0–14.0 (1 candidate)"));
  CHECK(has(md, "against the target of 60 s"));
}

TEST_CASE("real tiles: plots without vehicles, exact Poisson per hectare; v1, stopped and not-run tiles") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "report-real" / "plots";
  fs::remove_all(root);
  plots(root);
  write(root / "townB" / "tile.time", "180.0 100000 170 3\n");  // stopped by the time box: no detections
  write(root / "labels" / "townB.truth.json",
        R"({"format": "canopy.scene_truth", "version": 1, "extent": [10, 10], "vehicles": []})");
  std::vector<report::RealTile> tiles;
  tiles.push_back(report::read_real_tile({"plotA", (root / "plotA").string(), ""}));
  tiles.push_back(report::read_real_tile({"plotB", (root / "plotB").string(), ""}));
  tiles.push_back(report::read_real_tile(
      {"townB", (root / "townB").string(), (root / "labels" / "townB.truth.json").string()}));
  tiles.push_back(report::read_real_tile({"gone", (root / "gone").string(), ""}));
  // A plot a tool refused: its error line quoted from the tile's logs.
  write(root / "closed" / "tile.time", "3.2 50000 1.5 0.5\n");
  write(root / "closed" / "cands.mk.log", "collect: nothing here\n");
  write(root / "closed" / "detect.log",
        "detect: read: 59712 points (0.467 s)\ndetect: error: closed.laz: found ground in only 18.0% | of "
        "the cells\n");
  tiles.push_back(report::read_real_tile({"closed", (root / "closed").string(), ""}));
  const report::RealTile& a = tiles[0];
  CHECK(a.area_ha == Approx(0.25));
  CHECK(a.density == Approx(59712 / 2500.0));
  CHECK(a.density_from != "index");
  CHECK(a.warning == "most candidates are too sparse");
  CHECK(tiles[1].version == 1);
  CHECK(tiles[1].by_reason.at("none") == 3);
  CHECK(tiles[1].by_reason.at("failed") == 4);
  CHECK(tiles[2].ran);
  CHECK_FALSE(tiles[2].finished);
  CHECK_FALSE(tiles[3].ran);
  CHECK(tiles[2].error.empty());  // stopped: no tool's error
  CHECK(tiles[4].ran);
  CHECK_FALSE(tiles[4].finished);
  CHECK(tiles[4].error == "detect: error: closed.laz: found ground in only 18.0% | of the cells");

  const std::string md = report::real_markdown(tiles, 180);
  INFO(md);
  // 2 on 0.25 ha: 8 per ha, Garwood [0.2422, 7.2247] / 0.25.
  CHECK(has(md, "| plotA | 23.9 | 0.25 | 2 | 8.0 | [1.0, 28.9] |"));
  // 0 on 0.25 ha: [0, 3.6889] / 0.25.
  CHECK(has(md, "| plotB | 8.0 | 0.25 | 0 | 0.0 | [0.0, 14.8] |"));
  // Both: 2 on 0.5 ha; by density band, plotA alone at 10 points/m² or more, plotB alone under.
  CHECK(has(md, "| **all plots** | | 0.50 | 2 | 4.0 | [0.5, 14.4] |"));
  CHECK(has(md, "| plots at 10 pts/m² or more | | 0.25 | 2 | 8.0 | [1.0, 28.9] |"));
  CHECK(has(md, "| plots under 10 pts/m² | | 0.25 | 0 | 0.0 | [0.0, 14.8] |"));
  CHECK(has(md,
            "With 2 false alarms on 0.50 ha the 95% interval reaches 14.4 per ha over all plots, and 28.9 "
            "per ha over the 0.25 ha at 10 pts/m² or more."));
  CHECK(has(md, "exact Poisson (Garwood) 95% interval"));
  CHECK(
      has(md,
          "| plotA (no vehicles) | – | 0.25 | 23.9 (measured) | 59712 | 10 | 2 (0 / 2) | class: hatchback 1, "
          "class: van 1 | failed 1, too_sparse 5, vegetation_like 2 | most candidates are too sparse |"));
  CHECK(has(
      md,
      "| plotB (no vehicles) | – | 0.25 | 8.0 (measured) | 20000 | 7 | 0 (0 / 0) | – | failed 4, none 3 |"));
  CHECK(has(md, "**not finished** within the time box of 180 s"));
  CHECK(has(md, "| townB | 0 (0) | 0 | not finished |"));
  CHECK(has(md, "| gone (no vehicles) | – | – | – | – | not run |"));
  CHECK(has(md, "| plotB | 75.0 | 72.0 | 0.0 (0) | **no** |"));
  CHECK(has(md, "| townB | 180.0 (stopped) | 173.0 | 0.0 (0) | **no** |"));
  CHECK(has(md, "forest_bcts_1 is not committed"));
  CHECK(has(
      md,
      "| closed (no vehicles) | – | – | – | – | **failed**: `detect: error: closed.laz: found ground in only "
      "18.0% / of the cells` |"));
  CHECK(has(md, "| closed | – | – | failed | | |"));
  CHECK(has(md, "| closed | 3.2 (failed) | 2.0 | 0.0 (0) | **no** |"));
  CHECK(has(md, "Plots without vehicles: plotA, plotB, gone (not run), closed (failed)."));
}

TEST_CASE("real tiles: documents that do not add up are refused naming the file") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "report-real" / "bad";
  fs::remove_all(root);
  plots(root);
  // 10 candidates, 2 found, but only 3 rejected by reason.
  write(root / "plotA" / "detections.json", R"({"format": "canopy.detections", "version": 2, "candidates": 10,
    "found": 2, "by_level": {"model": 0, "class": 2}, "by_reason": {"too_sparse": 3}, "density": null,
    "warning": null, "detections": [)" + detection("c1", "hatchback", "car") +
                                                ", " + detection("c2", "van", "van") + "]}");
  const std::string path = (root / "plotA" / "detections.json").string();
  CHECK_THROWS_WITH(report::read_real_tile({"plotA", (root / "plotA").string(), ""}),
                    Catch::Contains(path) && Catch::Contains("is not found 2 + the rejected 3"));
  // A version this build does not know.
  write(root / "plotB" / "detections.json", R"({"format": "canopy.detections", "version": 3, "candidates": 0,
    "found": 0, "detections": []})");
  CHECK_THROWS_WITH(report::read_real_tile({"plotB", (root / "plotB").string(), ""}),
                    Catch::Contains("version 3 is not supported (this build reads versions 1 to 2)"));
  // A level that is neither.
  write(root / "plotB" / "detections.json", R"({"format": "canopy.detections", "version": 2, "candidates": 1,
    "found": 1, "by_level": {}, "by_reason": {}, "density": null, "warning": null,
    "detections": [{"candidate": "c1", "level": "part"}]})");
  CHECK_THROWS_WITH(report::read_real_tile({"plotB", (root / "plotB").string(), ""}),
                    Catch::Contains("detections[0].level must be model or class, not \"part\""));
}

TEST_CASE("real tiles: classify's ablation beside canopy, per tile and over the labelled tiles") {
  const fs::path root = fs::path(CANOPY_TEST_TMP) / "report-real" / "ablation";
  fs::remove_all(root);
  const fs::path labels = root / "labels";
  town(root / "real", labels);
  town(root / "abl", labels);
  plots(root / "real");
  plots(root / "abl");
  fs::remove_all(root / "abl" / "plotB");  // the ablation not run there
  // The ablation misses vehicle 6 (clear): its c06 becomes a false alarm far from everything.
  const fs::path score = root / "abl" / "townA" / "score.json";
  std::string text = common::read_file(score.string());
  const std::string hit =
      R"("candidate": "c06", "x": 0, "y": 0, "outcome": "right", "instance": 6, "true_model": "car")";
  REQUIRE(text.find(hit) != std::string::npos);
  text.replace(text.find(hit), hit.size(),
               R"("candidate": "c06", "x": 700, "y": 700, "outcome": "false_alarm")");
  write(score, text);
  const std::string truth = (labels / "townA.truth.json").string();
  std::vector<report::RealTile> tiles, abl;
  for (const char* dir : {"real", "abl"}) {
    auto& to = std::string(dir) == "real" ? tiles : abl;
    to.push_back(report::read_real_tile({"plotA", (root / dir / "plotA").string(), ""}));
    to.push_back(report::read_real_tile({"plotB", (root / dir / "plotB").string(), ""}));
    to.push_back(report::read_real_tile({"townA", (root / dir / "townA").string(), truth}));
  }
  CHECK(report::real_ablation_markdown(tiles, {}, "x.ini").empty());
  const std::string md = report::real_ablation_markdown(tiles, abl, "out/params/classify-bridge-0.ini");
  INFO(md);
  CHECK(has(md, "### classify's ablation on the real tiles"));
  CHECK(has(md, "parameters `out/params/classify-bridge-0.ini`"));
  CHECK(has(md, "| plotA (no vehicles) | false alarms | 2 = 8.0/ha [1.0, 28.9] | 2 = 8.0/ha [1.0, 28.9] |"));
  CHECK(has(md, "| plotB | run | finished | not run |"));
  CHECK(has(md, "| townA | recall, clear | 6/8 = 75.0% [40.9, 92.9] | 5/8 = 62.5% [30.6, 86.3] |"));
  CHECK(has(md, "| townA | recall, all | 8/10 = 80.0% [49.0, 94.3] | 7/10 = 70.0% [39.7, 89.2] |"));
  CHECK(has(md, "| townA | precision | 8/9 = 88.9% [56.5, 98.0] | 7/9 = 77.8% [45.3, 93.7] |"));
  CHECK(has(md, "| townA | class right | 7/8 = 87.5% [52.9, 97.8] | 6/7 = 85.7% [48.7, 97.4] |"));
  CHECK(!has(md, "all scored"));  // one labelled tile
  CHECK(!has(md, "REAL_CLASSIFY_ABLATION_2"));
  // The second ablation names itself and its make variable; its rows are the same.
  const std::string md2 =
      report::real_ablation_markdown(tiles, abl, "out/params/classify-tile-ground-0.ini", 1);
  CHECK(has(md2, "### classify's second ablation on the real tiles"));
  CHECK(has(md2, "parameters `out/params/classify-tile-ground-0.ini`"));
  CHECK(has(md2, "mk/real.mk REAL_CLASSIFY_ABLATION_2)"));
  CHECK(has(md2, "| townA | recall, clear | 6/8 = 75.0% [40.9, 92.9] | 5/8 = 62.5% [30.6, 86.3] |"));

  // The model level's ablation (an entry TILE_MODEL_DENSITY=<value>): its own heading, no classify
  // file, and each tile's model-level detections beside the same rows. The ablation's townA has one
  // of its class answers at the model level instead.
  const fs::path dets = root / "abl" / "townA" / "detections.json";
  text = common::read_file(dets.string());
  const std::string cls = R"("level": "class", "model": null)";
  REQUIRE(text.find(cls) != std::string::npos);
  text.replace(text.find(cls), cls.size(), R"("level": "model", "model": "sedan")");
  write(dets, text);
  abl.back() = report::read_real_tile({"townA", (root / "abl" / "townA").string(), truth});
  const std::string md4 = report::real_ablation_markdown(tiles, abl, "TILE_MODEL_DENSITY=50", 3);
  INFO(md4);
  CHECK(has(md4, "### The model level's ablation on the real tiles"));
  CHECK(has(md4, "classify.ini and `TILE_MODEL_DENSITY=50`"));
  CHECK(has(md4, "mk/real.mk REAL_CLASSIFY_ABLATION_4)"));
  CHECK(!has(md4, "classify's"));
  CHECK(has(md4, "| plotA (no vehicles) | model level detections | 0 | 0 |"));
  CHECK(has(md4, "| plotA (no vehicles) | false alarms | 2 = 8.0/ha [1.0, 28.9] | 2 = 8.0/ha [1.0, 28.9] |"));
  CHECK(has(md4, "| townA | model level detections | 0 | 1 |"));
  CHECK(has(md4, "| townA | recall, clear | 6/8 = 75.0% [40.9, 92.9] | 5/8 = 62.5% [30.6, 86.3] |"));
  CHECK(has(md4, "| **all tiles** | model level detections | 0 | 1 |"));
  // A classify ablation has no such rows.
  CHECK(!has(md2, "model level detections"));
}

TEST_CASE("real tiles: every tile committed in share/real has its source and licence in the table") {
  // A tile added to share/real/ without a source would show "–" in the report's source column
  // (stop 66's 23 forest plots did until stop 67).
  int tiles = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(CANOPY_SOURCE_DIR) / "share" / "real")) {
    if (entry.path().extension() != ".laz") continue;
    const std::string name = entry.path().stem().string();
    INFO(name);
    const std::string source = report::real_tile_source(name);
    CHECK(source != "–");
    CHECK(has(source, "("));  // the licence, in parentheses
    ++tiles;
  }
  CHECK(tiles >= 27);
  CHECK(report::real_tile_source("forest_neon_teak_043") == "NEON AOP 2018, Teakettle (CC0)");
  CHECK(report::real_tile_source("forest_ign_loiret_crop2") == "IGN LiDAR HD, Loiret forest (Etalab 2.0)");
  CHECK(report::real_tile_source("somewhere_else") == "–");
}
