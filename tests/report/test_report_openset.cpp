// The open-set section (issue 29): the library's distances.csv read with its checks, each test
// instance's nearest modelbase entry, and instance accuracy over a hand-made score's matches.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/documents/experiment_manifest.h"
#include "canopy/documents/match_result.h"
#include "canopy/documents/segment_graph.h"
#include "canopy/documents/scene_score.h"
#include "one_trial.h"
#include "report/openset_section.h"
#include "support/cli.h"

using namespace canopy;

namespace {

const char* const kDistances =
    "test,class,modelbase,distance_m,rank\n"
    "gz_suv,car,ch_nissan_patrol,0.1500,1\n"
    "gz_suv,car,gz_prius_hybrid,0.2500,2\n"
    "ch_man_7t,truck,ch_man_5t,0.0800,1\n"
    "ch_man_7t,truck,om_truck_example,0.4000,2\n";

documents::ScoreMatch match(const std::string& truth, const std::string& outcome, const std::string& level,
                            const std::string& model, const std::string& cls) {
  documents::ScoreMatch m;
  m.true_model = truth;
  m.outcome = outcome;
  m.level = level;
  if (!model.empty()) m.model = model;
  m.cls = cls;
  return m;
}

// A crops' score of 10 crops with one summary row per cover label in `covers` (the same counts).
std::string crops_score_json(const std::vector<std::string>& covers, int tp, int fp, int class_tp,
                             int class_fp, int found, int right) {
  std::string rows;
  for (const std::string& c : covers)
    rows += std::string(rows.empty() ? "" : ",") + R"({"cover": ")" + c +
            R"(", "noise_mm": "all", "tiles": 10, "true": 10, "tp": )" + std::to_string(tp) + R"(, "fp": )" +
            std::to_string(fp) + R"(, "class_tp": )" + std::to_string(class_tp) + R"(, "class_fp": )" +
            std::to_string(class_fp) + R"(, "found_any_level": )" + std::to_string(found) +
            R"(, "class_right_any_level": )" + std::to_string(right) + "}";
  return R"({"format": "canopy.scene_score", "version": 1,
    "params": {"match_radius_m": 1.5, "cover_bins": [0, 1], "flip_threshold_deg": 90},
    "tiles": [{"detections": "c/d.json", "cover": "car", "noise_mm": 0, "area_ha": 0.04}],
    "summary": [)" +
         rows + R"(], "pr": [], "models": [], "cover_bins": [], "reliability": [], "matches": []})";
}
documents::SceneScore crops_score(const std::vector<std::string>& covers, int tp, int fp, int class_tp,
                                  int class_fp, int found, int right) {
  return documents::read_scene_score(crops_score_json(covers, tp, fp, class_tp, class_fp, found, right),
                                     "crops.json");
}

// A report run over hand-made open-set scores: each (name, score.json text) written as
// dir/name/score.json (the tiles') and dir/name/crops/score.json, and a one-trial manifest.
struct OpensetRun {
  std::filesystem::path dir;
  std::string path(const std::string& name, bool crops) const {
    return (dir / name / (crops ? "crops/score.json" : "score.json")).string();
  }
  // report --manifest ... --openset and --openset-crops of the score named "canopy".
  std::string command() const {
    return std::string(CANOPY_BIN_DIR) + "/report --manifest " + (dir / "experiment.txt").string() +
           " --openset " + path("canopy", false) + " --openset-crops " + path("canopy", true);
  }
};
OpensetRun openset_run(const std::string& name, const std::vector<std::pair<std::string, std::string>>& scores) {
  const OpensetRun run{test::fresh_dir("report", name)};
  for (const auto& [n, json] : scores) {
    test::write_file(run.dir / n / "score.json", json);
    test::write_file(run.dir / n / "crops" / "score.json", json);
  }
  std::ofstream(run.dir / "experiment.txt")
      << documents::write_experiment_manifest(report::testing::one_trial_manifest(run.dir));
  return run;
}

}  // namespace

TEST_CASE("open set: distances.csv gives each test instance's nearest modelbase entry") {
  const report::OpensetDistances d = report::parse_openset_distances(kDistances, "distances.csv");
  REQUIRE(d.size() == 2);
  REQUIRE(d.at("gz_suv").size() == 2);
  CHECK(d.at("gz_suv")[1].distance_m == Approx(0.25));
  CHECK(report::openset_nearest_entry(d, "gz_suv") == "car__ch_nissan_patrol");
  CHECK(report::openset_nearest_entry(d, "ch_man_7t") == "truck__ch_man_5t");
  CHECK(report::openset_nearest_entry(d, "gz_hatchback").empty());
}

TEST_CASE("open set: a malformed distances.csv is refused naming the file and the line") {
  const auto refuses = [](const std::string& text, const std::string& what) {
    try {
      report::parse_openset_distances(text, "lib/distances.csv");
      FAIL("accepted: " << text);
    } catch (const common::DataError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find("lib/distances.csv") != std::string::npos);
      CHECK(std::string(e.what()).find(what) != std::string::npos);
    }
  };
  refuses("", "empty");
  refuses("test,class,modelbase,distance\n", "header");
  refuses("test,class,modelbase,distance_m,rank\ngz_suv,car,x,0.1\n", "line 2: five fields");
  refuses("test,class,modelbase,distance_m,rank\ngz_suv,car,x,0x1,1\n", "not a distance");
  refuses("test,class,modelbase,distance_m,rank\ngz_suv,car,x,-0.1,1\n", "not a distance");
  refuses("test,class,modelbase,distance_m,rank\ngz_suv,car,x,0.1,2\n", "ranks must run");
  refuses("test,class,modelbase,distance_m,rank\ngz_suv,car,x,0.2,1\ngz_suv,car,y,0.1,2\n", "by distance");
}

TEST_CASE("open set: instance accuracy counts the model-level answers naming the nearest instance") {
  const report::OpensetDistances d = report::parse_openset_distances(kDistances, "distances.csv");
  documents::SceneScore s;
  s.matches = {
      match("gz_suv", "right", "model", "car__ch_nissan_patrol", "car"),       // the nearest: counts
      match("gz_suv", "right", "model", "car__gz_prius_hybrid", "car"),        // right class, not nearest
      match("gz_suv", "wrong", "model", "truck__ch_man_5t", "truck"),          // wrong class, not nearest
      match("gz_suv", "right", "class", "", "car"),                            // class level: not counted
      match("gz_suv", "missed", "model", "", ""),                              // missed: not counted
      match("ch_man_7t", "right", "model", "truck__ch_man_5t", "truck"),       // the nearest
      match("gz_hatchback", "right", "model", "car__ch_nissan_patrol", "car")  // no distances: not counted
  };
  const report::InstanceTally t = report::openset_instance_tally(s, d);
  CHECK(t.model_answers == 4);
  CHECK(t.nearest == 2);
  const std::string md = report::openset_markdown(s, "score.json", &s, "crops.json", d, "distances.csv");
  // 2/4 with Wilson's interval [15.0, 85.0], for the tiles and for the crops.
  const std::string line =
      "model-level answers naming the test instance's nearest modelbase instance): 2/4 = 50.0%";
  const auto first = md.find(line);
  REQUIRE(first != std::string::npos);
  CHECK(md.find(line, first + 1) != std::string::npos);
  CHECK(md.find("[15.0, 85.0]") != std::string::npos);
  CHECK(md.find("### Single-vehicle crops of the unseen test instances") != std::string::npos);
  CHECK(md.find("| gz_suv | ch_nissan_patrol (0.150 m; gz_prius_hybrid 0.250 m) | 4/5 | 3 / 1 | 1/3 |") !=
        std::string::npos);
  CHECK(md.find("| ch_man_7t | ch_man_5t (0.080 m; om_truck_example 0.400 m) | 1/1 | 1 / 0 | 1/1 |") !=
        std::string::npos);
}

TEST_CASE("open set: the crops' table gives Wilson intervals on the counts, one crop per tile") {
  // 10 crops of cars: 8 found (5 at the model level, 3 at the class level), 6 of them the right
  // class, one false alarm. Wilson: 8/10 [49.0, 94.3], 6/8 [40.9, 92.9], 6/10 [31.3, 83.2],
  // 2/8 [7.1, 59.1].
  const documents::SceneScore crops = crops_score({"car", "all"}, 5, 1, 3, 0, 8, 6);
  documents::SceneScore tiles;
  const std::string md = report::openset_markdown(tiles, "score.json", &crops, "crops.json");
  CHECK(
      md.find("| car | 10 | 8 (5 + 3) | 8/10 = 80.0% [49.0, 94.3] | 6/8 = 75.0% [40.9, 92.9] | 6/10 = 60.0% "
              "[31.3, 83.2] | 2/8 = 25.0% [7.1, 59.1] | 1 |") != std::string::npos);
  CHECK(md.find("| all | 10 | 8 (5 + 3) |") != std::string::npos);
  // Without distances: no instance accuracy line.
  CHECK(md.find("Instance accuracy") == std::string::npos);
}

TEST_CASE("open set: each classify ablation's name picks its subsection's heading and paragraph") {
  // The names in the open set's order (mk/openset.mk openset_classify_names).
  CHECK(report::openset_classify_ablation_names() ==
        std::vector<std::string>{"every-family", "no-envelope", "family-entries-1", "no-bed"});
  // Each name: its heading, a phrase of its paragraph, and no other name's heading.
  struct Expected {
    const char *name, *heading, *phrase;
  };
  const Expected expected[] = {
      {"every-family",
       "### Ablation: every classify family, no class envelope (`OPENSET_CLASSES_ONLY=0 "
       "OPENSET_CLASS_ENVELOPE=0`)",
       "`classify --class-envelope 0.05`, eighth round"},
      {"no-envelope",
       "### Ablation: no class envelope, the modelbase's classes only kept (`OPENSET_CLASS_ENVELOPE=0`)",
       "no class envelope (`classify --class-envelope 0`"},
      {"family-entries-1", "### Ablation: one entry keeps its family (`OPENSET_FAMILY_ENTRIES=1`)",
       "`classify --family-entries 2`, docs/decisions/open-set.md, eleventh round"},
      {"no-bed", "### Ablation: no pickup bed cue (`classify --min-bed 0`)",
       "`classify --min-bed 0.1`, docs/decisions/classify.md §39"},
  };
  // The crops: 10 cars, 9 found (4 + 5), 5 of them the right class. Wilson: 9/10 [59.6, 98.2], 5/9
  // [26.7, 81.1], 5/10 [23.7, 76.3], 4/9 [18.9, 73.3].
  const documents::SceneScore crops = crops_score({"car"}, 4, 0, 5, 2, 9, 5);
  documents::SceneScore tiles;
  for (const Expected& e : expected) {
    CAPTURE(e.name);
    const std::string md =
        report::openset_classify_ablation_markdown(e.name, tiles, "abl/score.json", &crops, "abl/crops.json");
    CHECK(md.rfind(std::string("\n") + e.heading + "\n\n", 0) == 0);
    CHECK(md.find(e.phrase) != std::string::npos);
    for (const Expected& other : expected)
      if (&other != &e) CHECK(md.find(other.heading) == std::string::npos);
    CHECK(md.find("(abl/score.json, abl/crops.json)") != std::string::npos);
    CHECK(md.find("| car | 10 | 9 (4 + 5) | 9/10 = 90.0% [59.6, 98.2] | 5/9 = 55.6% [26.7, 81.1] | 5/10 = "
                  "50.0% [23.7, 76.3] | 4/9 = 44.4% [18.9, 73.3] | 2 |") != std::string::npos);
    // Without the crops: the tiles' table alone, the same heading.
    const std::string tiles_only = report::openset_classify_ablation_markdown(e.name, tiles, "abl/score.json");
    CHECK(tiles_only.find(e.heading) != std::string::npos);
    CHECK(tiles_only.find("single-vehicle crops") == std::string::npos);
    CHECK(tiles_only.find("| cover | tiles | vehicles |") != std::string::npos);
    CHECK(tiles_only.find("(abl/score.json).") != std::string::npos);
  }
  // Any other name: a usage error naming the option and the names.
  CHECK_THROWS_AS(report::openset_classify_ablation_markdown("envelope", tiles, "abl/score.json"),
                  common::UsageError);
  CHECK_THROWS_WITH(report::openset_classify_ablation_markdown("envelope", tiles, "abl/score.json"),
                    Catch::Contains("--openset-classify-ablation: no ablation named \"envelope\"") &&
                        Catch::Contains("every-family, no-envelope, family-entries-1, no-bed"));
}

TEST_CASE("open set: collect's ablation (the model answer first) is its own subsection") {
  // 10 cars, 9 found (4 + 5), 5 of them the right class: the same table as the classify ablation's.
  const documents::SceneScore crops = crops_score({"car"}, 4, 0, 5, 2, 9, 5);
  documents::SceneScore tiles;
  const std::string md =
      report::openset_collect_ablation_markdown(tiles, "cabl/score.json", &crops, "cabl/crops.json");
  CHECK(
      md.find("### Ablation: the model answer first (`collect --contradicted-below 0 --refused-below 0`)") !=
      std::string::npos);
  CHECK(md.find("every classify family") == std::string::npos);
  CHECK(md.find("(cabl/score.json, cabl/crops.json)") != std::string::npos);
  CHECK(md.find("| car | 10 | 9 (4 + 5) | 9/10 = 90.0% [59.6, 98.2] | 5/9 = 55.6% [26.7, 81.1] |") !=
        std::string::npos);
  const std::string tiles_only = report::openset_collect_ablation_markdown(tiles, "cabl/score.json");
  CHECK(tiles_only.find("single-vehicle crops") == std::string::npos);
}

TEST_CASE("open set: each collect ablation is headed by what its options turn off") {
  const documents::SceneScore crops = crops_score({"car"}, 4, 0, 5, 2, 9, 5);
  documents::SceneScore tiles;
  const std::string first_heading =
      "### Ablation: the model answer first (`collect --contradicted-below 0 --refused-below 0`)";
  const std::string class_heading =
      "### Ablation: the sixth round's contradiction by class (`collect --contradiction-level class`)";
  // The list's first entry (commas, as mk/openset.mk passes it) is the section without options,
  // byte for byte; in either order, or separated by spaces, the same.
  const std::string none =
      report::openset_collect_ablation_markdown(tiles, "c1/score.json", &crops, "c1/crops.json");
  for (const char* o : {"--contradicted-below=0,--refused-below=0", "--refused-below=0,--contradicted-below=0",
                        "--contradicted-below=0 --refused-below=0"})
    CHECK(report::openset_collect_ablation_markdown(tiles, "c1/score.json", &crops, "c1/crops.json", o) == none);
  // The second: the contradiction by class, pointing to the thirteenth round, with its own paths.
  const std::string second = report::openset_collect_ablation_markdown(
      tiles, "c2/score.json", &crops, "c2/crops.json", "--contradiction-level=class");
  CHECK(second.find(class_heading) != std::string::npos);
  CHECK(second.find(first_heading) == std::string::npos);
  CHECK(second.find("`collect --contradiction-level group`, docs/decisions/open-set.md, thirteenth round") !=
        std::string::npos);
  CHECK(second.find("(c2/score.json, c2/crops.json)") != std::string::npos);
  CHECK(second.find("| car | 10 | 9 (4 + 5) | 9/10 = 90.0% [59.6, 98.2] | 5/9 = 55.6% [26.7, 81.1] |") !=
        std::string::npos);
  // Two sections, one per ablation, as main writes them in the list's order.
  const std::string both = none + second;
  CHECK(both.find(first_heading) < both.find(class_heading));
  // Any other options: the heading names them as collect takes them.
  const std::string other = report::openset_collect_ablation_markdown(tiles, "c3/score.json", nullptr, "",
                                                                      "--contradicted-below=0.3");
  CHECK(other.find("### Ablation: collect's options `collect --contradicted-below 0.3`") != std::string::npos);
  CHECK(other.find("model answer first") == std::string::npos);
  // Options text that is not collect options (a value not joined by "=") is a usage error naming
  // the flag.
  CHECK(report::collect_ablation_options("--a=1,--b=2 --c") ==
        std::vector<std::string>{"--a", "1", "--b", "2", "--c"});
  CHECK_THROWS_AS(report::collect_ablation_options("--a=1,class"), common::UsageError);
  CHECK_THROWS_AS(report::collect_ablation_options("--contradiction-level class"), common::UsageError);
  CHECK_THROWS_WITH(report::collect_ablation_options("--a=1,class"),
                    Catch::Contains("--openset-collect-ablation-options: \"class\""));
}

TEST_CASE("report --openset-classify-ablation: one subsection per NAME=SCORE in the order given") {
  namespace fs = std::filesystem;
  // Hand-made scores of 10 car crops each (tiles and crops alike), one per ablation with its own
  // counts: canopy 9 found, 9 right; every-family 8 found (4 + 4), 5 right; no-envelope 7 found
  // (3 + 4), 7 right; family-entries-1 8 found (4 + 4), 6 right; no-bed 10 found (0 + 10), 3 right.
  const OpensetRun run =
      openset_run("openset-classify-ablations", {{"canopy", crops_score_json({"car"}, 5, 0, 4, 0, 9, 9)},
                                                 {"all-off", crops_score_json({"car"}, 4, 1, 4, 0, 8, 5)},
                                                 {"envelope-off", crops_score_json({"car"}, 3, 0, 4, 0, 7, 7)},
                                                 {"family-1", crops_score_json({"car"}, 4, 0, 4, 0, 8, 6)},
                                                 {"bed-0", crops_score_json({"car"}, 0, 0, 10, 0, 10, 3)}});
  const fs::path& dir = run.dir;
  const auto path = [&](const std::string& name, bool crops) { return run.path(name, crops); };
  // Each ablation: its name, its scores' directory, its heading and its crops' row (Wilson's
  // intervals: 8/10 [49.0, 94.3], 5/8 [30.6, 86.3], 7/10 [39.7, 89.2], 7/7 [64.6, 100.0], 6/8
  // [40.9, 92.9], 10/10 [72.2, 100.0], 3/10 [10.8, 60.3]), in the order the command line gives
  // them (not the open set's: no-bed before family-entries-1).
  struct Ablation {
    std::string name, dir, heading, row;
  };
  const std::vector<Ablation> ablations = {
      {"every-family", "all-off", "### Ablation: every classify family, no class envelope",
       "| car | 10 | 8 (4 + 4) | 8/10 = 80.0% [49.0, 94.3] | 5/8 = 62.5% [30.6, 86.3] |"},
      {"no-envelope", "envelope-off", "### Ablation: no class envelope, the modelbase's classes only kept",
       "| car | 10 | 7 (3 + 4) | 7/10 = 70.0% [39.7, 89.2] | 7/7 = 100.0% [64.6, 100.0] |"},
      {"no-bed", "bed-0", "### Ablation: no pickup bed cue (`classify --min-bed 0`)",
       "| car | 10 | 10 (0 + 10) | 10/10 = 100.0% [72.2, 100.0] | 3/10 = 30.0% [10.8, 60.3] | 3/10 = 30.0% "
       "[10.8, 60.3] | 7/10 = 70.0% [39.7, 89.2] | 0 |"},
      {"family-entries-1", "family-1", "### Ablation: one entry keeps its family (`OPENSET_FAMILY_ENTRIES=1`)",
       "| car | 10 | 8 (4 + 4) | 8/10 = 80.0% [49.0, 94.3] | 6/8 = 75.0% [40.9, 92.9] | 6/10 = 60.0% [31.3, "
       "83.2] | 2/8 = 25.0% [7.1, 59.1] | 0 |"},
  };
  const auto option = [&](const Ablation& a) {
    return " --openset-classify-ablation " + a.name + "=" + path(a.dir, false) +
           " --openset-crops-classify-ablation " + a.name + "=" + path(a.dir, true);
  };
  const std::string report = run.command();
  std::string all, first_three, err;
  for (std::size_t i = 0; i < ablations.size(); ++i) {
    all += option(ablations[i]);
    if (i + 1 < ablations.size()) first_three += option(ablations[i]);
  }
  fs::create_directories(dir / "res");
  REQUIRE(test::sh(report + all + " --results " + (dir / "res").string(), dir / "err1.txt", &err) == 0);
  const std::string md = test::read_text(dir / "res" / "report.md");
  const auto section = md.find("## Open set: unseen vehicles");
  REQUIRE(section != std::string::npos);
  // canopy's own crops' row before the first ablation.
  const auto canopy_row = md.find("| car | 10 | 9 (5 + 4) | 9/10 = 90.0%");
  CHECK(canopy_row > section);
  std::size_t before = canopy_row;
  for (std::size_t i = 0; i < ablations.size(); ++i) {
    const Ablation& a = ablations[i];
    CAPTURE(a.name);
    const auto heading = md.find(a.heading);
    REQUIRE(heading != std::string::npos);
    CHECK(heading > before);  // after the one before it
    // Its own crops' row between its heading and the next one, and its paths.
    const auto next = i + 1 < ablations.size() ? md.find(ablations[i + 1].heading) : md.size();
    const auto row = md.find(a.row, heading);
    CHECK(row != std::string::npos);
    CHECK(row < next);
    CHECK(md.find("(" + path(a.dir, false) + ", " + path(a.dir, true) + ")", heading) < next);
    before = heading;
  }
  // Without the last one: the same report up to its subsection (here the last), and no such heading.
  fs::create_directories(dir / "res-three");
  REQUIRE(test::sh(report + first_three + " --results " + (dir / "res-three").string(), dir / "err2.txt",
                   &err) == 0);
  const std::string three = test::read_text(dir / "res-three" / "report.md");
  CHECK(three.find(ablations.back().heading) == std::string::npos);
  CHECK(three.size() < md.size());
  CHECK(md.substr(0, three.size()) == three);
  // Without its crops' score: the tiles' table alone for that one.
  fs::create_directories(dir / "res-tiles");
  REQUIRE(test::sh(report + " --openset-classify-ablation no-bed=" + path("bed-0", false) + " --results " +
                       (dir / "res-tiles").string(),
                   dir / "err3.txt", &err) == 0);
  const std::string tiles = test::read_text(dir / "res-tiles" / "report.md");
  const auto bed = tiles.find("### Ablation: no pickup bed cue");
  REQUIRE(bed != std::string::npos);
  CHECK(tiles.find("| car | 10 | 10 | 10 (0 + 10) |", bed) != std::string::npos);
  CHECK(tiles.find("The single-vehicle crops, the same ablation", bed) == std::string::npos);
  // Usage errors (exit 2, no report): the crops' score without its tiles', the ablation without
  // --openset, a name no ablation has, an argument that is not NAME=SCORE, a name given twice.
  const std::string bare =
      std::string(CANOPY_BIN_DIR) + "/report --manifest " + (dir / "experiment.txt").string();
  const std::string family = " --openset-classify-ablation family-entries-1=" + path("family-1", false);
  const std::pair<std::string, std::string> bad[] = {
      {report + " --openset-crops-classify-ablation no-bed=" + path("bed-0", true),
       "--openset-crops-classify-ablation no-bed needs --openset-classify-ablation no-bed"},
      {report + family + " --openset-crops-classify-ablation no-bed=" + path("bed-0", true),
       "--openset-crops-classify-ablation no-bed needs --openset-classify-ablation no-bed"},
      {bare + family, "--openset-classify-ablation needs --openset"},
      {report + " --openset-classify-ablation bed=" + path("bed-0", false),
       "--openset-classify-ablation: no ablation named \"bed\""},
      {report + " --openset-classify-ablation " + path("bed-0", false), "is not NAME=SCORE"},
      {report + " --openset-classify-ablation no-bed=", "is not NAME=SCORE"},
      {report + family + family, "--openset-classify-ablation: family-entries-1 given twice"},
      {report + family + " --openset-crops-classify-ablation family-entries-1=" + path("family-1", true) +
           " --openset-crops-classify-ablation family-entries-1=" + path("family-1", true),
       "--openset-crops-classify-ablation: family-entries-1 given twice"},
  };
  for (const auto& [command, message] : bad) {
    CAPTURE(command);
    fs::remove_all(dir / "res-bad");
    fs::create_directories(dir / "res-bad");
    CHECK(test::sh(command + " --results " + (dir / "res-bad").string(), dir / "err4.txt", &err) == 2);
    CHECK(err.find(message) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "res-bad" / "report.md"));
  }
  // A damaged score of one ablation's crops: exit 1 naming the file, no report.
  test::write_file(dir / "envelope-off" / "crops" / "score.json", "{\"format\": \"canopy.scene_score\"");
  fs::remove_all(dir / "res-bad");
  fs::create_directories(dir / "res-bad");
  CHECK(test::sh(report + all + " --results " + (dir / "res-bad").string(), dir / "err5.txt", &err) == 1);
  CHECK(err.find(path("envelope-off", true)) != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "res-bad" / "report.md"));
}

TEST_CASE("open set: verify's ablation (no upright bound) is its own subsection, the tiles only") {
  // A tiles' score with one cover row (the crops' helper's document: 10 vehicles, 9 found).
  const documents::SceneScore tiles = crops_score({"light"}, 4, 1, 5, 2, 9, 5);
  const std::string md = report::openset_verify_ablation_markdown(tiles, "vabl/score.json", "--max-tilt=180");
  CHECK(md.find("### Ablation: no upright bound (`verify --max-tilt=180`)") != std::string::npos);
  CHECK(md.find("more than `verify --max-tilt` (40° in share/params/verify.ini)") != std::string::npos);
  CHECK(md.find("(vabl/score.json).") != std::string::npos);
  CHECK(md.find("| cover | tiles | vehicles | found (model + class) |") != std::string::npos);
  CHECK(md.find("| light | ") != std::string::npos);
  CHECK(md.find("single-vehicle crops") == std::string::npos);
  // Any other options: the heading names them.
  const std::string other = report::openset_verify_ablation_markdown(tiles, "v2/score.json", "--top-k=3");
  CHECK(other.find("### Ablation: verify's options `--top-k=3`") != std::string::npos);
  CHECK(other.find("upright") == std::string::npos);
}

TEST_CASE(
    "open set: the tiles' reliability table, each bin of >= 20 answers judged; none for a score without "
    "one") {
  // Tiles: model answers never right (no test instance is in the modelbase), 22 nones all right at a
  // stated 0.83 (under-confident by 17 points: outside ±10), 21 class answers at 0.95, 20 right.
  const documents::SceneScore tiles = documents::read_scene_score(
      R"({"format": "canopy.scene_score", "version": 1,
    "params": {"match_radius_m": 1.5, "cover_bins": [0, 1], "flip_threshold_deg": 90},
    "tiles": [{"detections": "t/d.json", "cover": "light", "noise_mm": 0, "area_ha": 0.09}],
    "summary": [], "pr": [], "models": [], "cover_bins": [],
    "reliability": [
      {"level": "model", "confidence_lo": 0.2, "confidence_hi": 0.3, "answers": 3, "right": 0,
       "mean_confidence": 0.25, "rate": 0, "rate_lo": 0, "rate_hi": 0.56},
      {"level": "class", "confidence_lo": 0.9, "confidence_hi": 1, "answers": 21, "right": 20,
       "mean_confidence": 0.95, "rate": 0.952, "rate_lo": 0.773, "rate_hi": 0.992},
      {"level": "none", "confidence_lo": 0.7, "confidence_hi": 0.8, "answers": 0, "right": 0,
       "mean_confidence": null, "rate": null, "rate_lo": null, "rate_hi": null},
      {"level": "none", "confidence_lo": 0.8, "confidence_hi": 0.9, "answers": 22, "right": 22,
       "mean_confidence": 0.83, "rate": 1, "rate_lo": 0.851, "rate_hi": 1}],
    "matches": []})",
      "score.json");
  const documents::SceneScore crops = crops_score({"car", "all"}, 5, 1, 3, 0, 8, 6);  // no reliability rows
  const std::string md = report::openset_markdown(tiles, "score.json", &crops, "crops.json");
  CHECK(md.find("**Reliability** of the tiles' answers") != std::string::npos);
  CHECK(md.find("| model | 0.2–0.3 | 3 | 0 = 0.0% [0.0, 56.0] | 25.0% | – (< 20) |") != std::string::npos);
  CHECK(md.find("| class | 0.9–1.0 | 21 | 20 = 95.2% [77.3, 99.2] | 95.0% | yes |") != std::string::npos);
  CHECK(md.find("| none | 0.8–0.9 | 22 | 22 = 100.0% [85.1, 100.0] | 83.0% | **no** |") != std::string::npos);
  CHECK(md.find("| none | 0.7–0.8 |") == std::string::npos);  // an empty bin is not shown
  CHECK(md.find("Bins of at least 20 answers outside ±10 points: 1.") != std::string::npos);
  // The crops' score has no reliability rows: no table of theirs.
  CHECK(md.find("**Reliability** of the crops' answers") == std::string::npos);
}
