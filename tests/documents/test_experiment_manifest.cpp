// documents/experiment_manifest.h and documents/tile_list.h: the manifests make writes for
// report and score read back record for record; malformed ones are refused naming the file and
// the line.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "canopy/common/error.h"
#include "canopy/documents/experiment_manifest.h"
#include "canopy/documents/tile_list.h"

using namespace canopy;

namespace {

// Two objects, one scene, two noise levels, as make writes them (objects then scenes then noises).
const char* kManifest =
    "# the experiment (Makefile.experiments)\n"
    "trial sedan circle 0 out/sedan/circle/noise-0\n"
    "trial sedan circle 8 out/sedan/circle/noise-8\n"
    "trial tank circle 0 out/tank/circle/noise-0   # a comment after a record\n"
    "\n"
    "trial tank circle 8 out/tank/circle/noise-8\r\n"
    "model sedan out/modelbase/sedan.json\n"
    "render tank circle out/tank/circle/scan.pcd\n"
    "ablation ncut-squared ncut+--exponent+squared\n"
    "ablation-trial ncut-squared sedan circle 0 a/s0.json\n"
    "ablation-trial ncut-squared sedan circle 8 a/s8.json\n"
    "ablation-trial ncut-squared tank circle 0 a/t0.json\n"
    "ablation-trial ncut-squared tank circle 8 a/t8.json\n"
    "figure figures/grid-circle.png\n"
    "figure pictures/tank-circle.png\n"
    "real forest_lareunion out/real/forest_lareunion\n"
    "real urban_1 out/real/urban_1 share/real/urban_1.truth.json\n"
    "real-ablation urban_1 out/real-ablation/urban_1 bench/real/no-bridge.ini\n"
    "real-ablation urban_1 out/real-ablation-2/urban_1 bench/real/no-ground.ini\n"
    "density 10 0.667 res/density/d10/score.json bench/density/floor.ini "
    "res/density/d10/class-ablation/score.json\n"
    "density 25.5 0.418 res/density/d25.5/score.json\n"
    "density-verify pixel 25.5 --seen-spacing=0 res/density/d25.5/verify-ablation/score.json\n"
    "density-classify pixel 25.5 bench/density/shoulder.ini res/density/d25.5/class-ablation-2/score.json\n"
    "density-classify pixel 25.5 bench/density/sampled.ini res/density/d25.5/class-ablation-3/score.json\n"
    "density-detect pixel 25.5 bench/density/end-gap-0.ini res/density/d25.5/detect-ablation/score.json\n"
    "density-sensor 10 als_qL1 res/density/als_qL1-10/score.json\n"
    "density-verify als_qL1 10 --seen-spacing=0+--top-k=5 res/density/als_qL1-10/verify-ablation/score.json\n"
    "density-sensor 25 als_qL1 res/density/als_qL1-25/score.json bench/density/late.ini "
    "res/density/als_qL1-25/class-ablation/score.json\n"
    "density-classify als_qL1 25 bench/density/shoulder.ini "
    "res/density/als_qL1-25/class-ablation-2/score.json\n"
    "density-detect als_qL1 25 bench/density/end-gap-0.ini "
    "res/density/als_qL1-25/detect-ablation/score.json\n"
    "density-detect als_qL1 25 bench/density/other.ini res/density/als_qL1-25/detect-ablation-2/score.json\n";

std::string refusal(const std::string& text) {
  try {
    documents::parse_experiment_manifest(text, "experiment.txt");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "experiment.txt");
    return e.what();
  }
  return "";
}

std::string tile_list_refusal(const std::string& text) {
  try {
    documents::parse_tile_list(text, "tiles.txt");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "tiles.txt");
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("experiment manifest: every record read, the grid in order of first appearance") {
  const documents::ExperimentManifest m = documents::parse_experiment_manifest(kManifest, "experiment.txt");
  CHECK(m.objects == std::vector<std::string>{"sedan", "tank"});
  CHECK(m.scenes == std::vector<std::string>{"circle"});
  CHECK(m.noises == std::vector<int>{0, 8});
  REQUIRE(m.trials.size() == 4);
  CHECK(m.trial_dir("tank", "circle", 8) == "out/tank/circle/noise-8");  // its CR dropped
  CHECK(m.trial_dir("tank", "circle", 0) == "out/tank/circle/noise-0");  // its comment dropped
  CHECK(m.trial_dir("tank", "flyby", 0).empty());
  CHECK(m.models.at("sedan") == "out/modelbase/sedan.json");
  CHECK(m.models.count("tank") == 0);
  CHECK(m.renders.at("tank/circle") == "out/tank/circle/scan.pcd");
  REQUIRE(m.ablations.size() == 1);
  CHECK(m.ablations[0].name == "ncut-squared");
  CHECK(m.ablations[0].change == "ncut --exponent squared");
  REQUIRE(m.ablations[0].trials.size() == 4);
  CHECK(m.ablations[0].trials[2].object == "tank");
  CHECK(m.ablations[0].trials[2].path == "a/t0.json");
  CHECK(m.figures == std::vector<std::string>{"figures/grid-circle.png", "pictures/tank-circle.png"});
  REQUIRE(m.real.size() == 2);
  CHECK(m.real[0].truth.empty());
  CHECK(m.real[1].dir == "out/real/urban_1");
  CHECK(m.real[1].truth == "share/real/urban_1.truth.json");
  // Written and read again: the same manifest.
  const documents::ExperimentManifest again =
      documents::parse_experiment_manifest(documents::write_experiment_manifest(m), "again.txt");
  CHECK(documents::write_experiment_manifest(again) == documents::write_experiment_manifest(m));
  CHECK(again.trials.size() == 4);
  CHECK(again.ablations[0].change == "ncut --exponent squared");
  CHECK(again.real[1].truth == m.real[1].truth);
  REQUIRE(m.density.size() == 2);
  CHECK(m.density[1].level == 25.5);
  CHECK(m.density[1].spacing == 0.418);
  CHECK(m.density[0].score == "res/density/d10/score.json");
  REQUIRE(again.density.size() == 2);
  CHECK(again.density[1].level == 25.5);
  CHECK(m.density[0].sensor.empty());
  REQUIRE(m.density_sensor.size() == 2);
  CHECK(m.density_sensor[0].level == 10);
  CHECK(m.density_sensor[1].sensor == "als_qL1");
  CHECK(m.density_sensor[1].spacing == 0);
  CHECK(m.density_sensor[1].score == "res/density/als_qL1-25/score.json");
  CHECK(m.density_sensor[0].classify.change.empty());
  CHECK(m.density_sensor[0].classify.score.empty());
  CHECK(m.density_sensor[1].classify.change == "bench/density/late.ini");
  CHECK(m.density_sensor[1].classify.score == "res/density/als_qL1-25/class-ablation/score.json");
  REQUIRE(again.density_sensor.size() == 2);
  CHECK(again.density_sensor[1].sensor == "als_qL1");
  CHECK(again.density_sensor[1].classify.score == "res/density/als_qL1-25/class-ablation/score.json");
  // verify's ablation on a rung of each ladder (blanks restored), none on the others; classify's on
  // a real tile.
  CHECK(m.density[0].verify.score.empty());
  CHECK(m.density[0].classify.change == "bench/density/floor.ini");
  CHECK(m.density[0].classify.score == "res/density/d10/class-ablation/score.json");
  CHECK(m.density[1].classify.score.empty());
  CHECK(again.density[0].classify.change == "bench/density/floor.ini");
  CHECK(m.density[1].verify.change == "--seen-spacing=0");
  CHECK(m.density[1].verify.score == "res/density/d25.5/verify-ablation/score.json");
  CHECK(m.density_sensor[0].verify.change == "--seen-spacing=0 --top-k=5");
  CHECK(m.density_sensor[0].verify.score == "res/density/als_qL1-10/verify-ablation/score.json");
  CHECK(m.density_sensor[1].verify.score.empty());
  // classify's second and third ablations (density-classify), after their rung's record, in order.
  CHECK(m.density[0].classify_more.empty());
  REQUIRE(m.density[1].classify_more.size() == 2);
  CHECK(m.density[1].classify_more[0].change == "bench/density/shoulder.ini");
  CHECK(m.density[1].classify_more[0].score == "res/density/d25.5/class-ablation-2/score.json");
  CHECK(m.density[1].classify_more[1].change == "bench/density/sampled.ini");
  CHECK(m.density[1].classify_more[1].score == "res/density/d25.5/class-ablation-3/score.json");
  CHECK(m.density_sensor[0].classify_more.empty());
  REQUIRE(m.density_sensor[1].classify_more.size() == 1);
  CHECK(m.density_sensor[1].classify_more[0].change == "bench/density/shoulder.ini");
  CHECK(m.density_sensor[1].classify_more[0].score == "res/density/als_qL1-25/class-ablation-2/score.json");
  REQUIRE(again.density[1].classify_more.size() == 2);
  CHECK(again.density[1].classify_more[1].score == m.density[1].classify_more[1].score);
  CHECK(again.density_sensor[1].classify_more[0].change == "bench/density/shoulder.ini");
  // detect's ablations (density-detect), after their rung's record, in order.
  CHECK(m.density[0].detect.empty());
  REQUIRE(m.density[1].detect.size() == 1);
  CHECK(m.density[1].detect[0].change == "bench/density/end-gap-0.ini");
  CHECK(m.density[1].detect[0].score == "res/density/d25.5/detect-ablation/score.json");
  CHECK(m.density[1].classify_more.size() == 2);  // not taken for classify's
  CHECK(m.density_sensor[0].detect.empty());
  REQUIRE(m.density_sensor[1].detect.size() == 2);
  CHECK(m.density_sensor[1].detect[1].change == "bench/density/other.ini");
  CHECK(m.density_sensor[1].detect[1].score == "res/density/als_qL1-25/detect-ablation-2/score.json");
  REQUIRE(again.density_sensor[1].detect.size() == 2);
  CHECK(again.density_sensor[1].detect[0].score == m.density_sensor[1].detect[0].score);
  CHECK(again.density[1].detect[0].change == "bench/density/end-gap-0.ini");
  CHECK(again.density[1].verify.score == m.density[1].verify.score);
  CHECK(again.density_sensor[0].verify.change == "--seen-spacing=0 --top-k=5");
  // classify's ablations of a real tile, in the manifest's order.
  CHECK(m.real[0].ablations.empty());
  REQUIRE(m.real[1].ablations.size() == 2);
  CHECK(m.real[1].ablations[0].dir == "out/real-ablation/urban_1");
  CHECK(m.real[1].ablations[0].config == "bench/real/no-bridge.ini");
  CHECK(m.real[1].ablations[1].dir == "out/real-ablation-2/urban_1");
  CHECK(m.real[1].ablations[1].config == "bench/real/no-ground.ini");
  REQUIRE(again.real[1].ablations.size() == 2);
  CHECK(again.real[1].ablations[1].dir == "out/real-ablation-2/urban_1");
  CHECK(documents::write_experiment_manifest(again) == documents::write_experiment_manifest(m));
}

TEST_CASE("experiment manifest: malformed records and grids are refused naming the line") {
  const std::string t = "trial sedan circle 0 d0\n";
  CHECK(refusal("").find("lists no trial") != std::string::npos);
  CHECK(refusal("# only a comment\n").find("lists no trial") != std::string::npos);
  CHECK(refusal(t + "trials sedan circle 0 d\n").find("line 2: unknown record 'trials'") != std::string::npos);
  CHECK(refusal("trial sedan circle 0\n").find("line 1: expected 'trial OBJECT SCENE NOISE_MM DIR'") !=
        std::string::npos);
  CHECK(refusal(t + t).find("line 2: a second trial sedan circle 0") != std::string::npos);
  CHECK(refusal("trial sedan circle 8mm d\n").find("line 1: noise '8mm'") != std::string::npos);
  CHECK(refusal("trial sedan circle 0x10 d\n").find("noise '0x10'") != std::string::npos);
  CHECK(refusal("trial sedan circle 2000000 d\n").find("noise '2000000'") != std::string::npos);
  CHECK(refusal("trial se/dan circle 0 d\n").find("object 'se/dan' is not a word") != std::string::npos);
  // Not a full grid: sedan has noise 8, tank has not.
  CHECK(refusal(t + "trial sedan circle 8 d8\ntrial tank circle 0 t0\n").find("not a full grid") !=
        std::string::npos);
  CHECK(refusal(t + "trial sedan circle 8 d8\ntrial tank circle 0 t0\n").find("no trial tank circle 8") !=
        std::string::npos);
  CHECK(refusal(t + "model sedan a\nmodel sedan b\n").find("line 3: a second model sedan") != std::string::npos);
  CHECK(refusal(t + "render sedan circle a\nrender sedan circle b\n").find("line 3: a second render") !=
        std::string::npos);
  CHECK(refusal(t + "ablation-trial x sedan circle 0 m\n").find("line 2: ablation 'x' is not declared") !=
        std::string::npos);
  CHECK(refusal(t + "ablation x a+b\nablation x a+b\n").find("line 3: a second ablation x") !=
        std::string::npos);
  CHECK(refusal(t + "ablation x a+b\n").find("ablation x has no trial sedan circle 0") != std::string::npos);
  CHECK(refusal(t + "ablation x a+b\nablation-trial x tank circle 0 m\n").find("that is not a trial") !=
        std::string::npos);
  CHECK(refusal(t + "ablation x a+b\nablation-trial x sedan circle 0 m\nablation-trial x sedan circle 0 m\n")
            .find("line 4: a second trial sedan circle 0 of ablation x") != std::string::npos);
  CHECK(refusal(t + "figure\n").find("line 2: expected 'figure PATH'") != std::string::npos);
  CHECK(refusal(t + "real a d\nreal a e\n").find("line 3: a second real tile a") != std::string::npos);
  CHECK(refusal(t + "real a d t x\n").find("line 2: expected 'real NAME DIR [TRUTH]'") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5\n")
            .find("line 2: expected 'density LEVEL SPACING SCORE [ABLATION_CONFIG ABLATION_SCORE]'") !=
        std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s a.ini\n").find("line 2: density: an ablation needs") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s a.ini b c\n").find("line 2: expected 'density LEVEL") !=
        std::string::npos);
  CHECK(refusal(t + "density ten 0.5 s\n").find("line 2: density level 'ten' is not a number") !=
        std::string::npos);
  CHECK(refusal(t + "density 10 0 s\n").find("pixel spacing '0'") != std::string::npos);
  CHECK(refusal(t + "density 50 0.3 s\ndensity 25 0.4 s\n").find("line 3: density level 25 does not rise") !=
        std::string::npos);
  CHECK(refusal(t + "density-sensor 10 als_qL1\n")
            .find("line 2: expected 'density-sensor LEVEL PRESET SCORE [ABLATION_CONFIG ABLATION_SCORE]'") !=
        std::string::npos);
  CHECK(refusal(t + "density-sensor 10 als_qL1 s a.ini\n").find("line 2: density-sensor: an ablation needs") !=
        std::string::npos);
  CHECK(refusal(t + "density-sensor 10 als_qL1 s a.ini b c\n").find("line 2: expected 'density-sensor") !=
        std::string::npos);
  CHECK(refusal(t + "density-sensor -5 als_qL1 s\n").find("line 2: density level '-5'") != std::string::npos);
  CHECK(refusal(t + "density-sensor 50 als_qL1 s\ndensity-sensor 25 als_qL1 s\n")
            .find("line 3: density-sensor level 25 does not rise") != std::string::npos);
  CHECK(refusal(t + "density-sensor 10 als_qL1 s\ndensity-sensor 25 uav s\n")
            .find("line 3: density-sensor preset uav is not the one before it (als_qL1)") != std::string::npos);
  CHECK(refusal(t + "density-sensor 10 a/b s\n").find("line 2:") != std::string::npos);
  CHECK(refusal(t + "real a d\nreal-ablation a e\n").find("line 3: expected 'real-ablation NAME DIR CONFIG'") !=
        std::string::npos);
  CHECK(refusal(t + "real a d\nreal-ablation b e c.ini\n").find("line 3: real-ablation b does not follow") !=
        std::string::npos);
  CHECK(refusal(t + "real a d\nreal-ablation a e c.ini\nreal-ablation a e c.ini\n")
            .find("line 4: a second real-ablation a") != std::string::npos);
  // A second ablation of the same tile in the first's directory, or with its parameters, is refused.
  CHECK(refusal(t + "real a d\nreal-ablation a e c.ini\nreal-ablation a e b.ini\n")
            .find("line 4: a second real-ablation a with e c.ini") != std::string::npos);
  CHECK(refusal(t + "real a d\nreal-ablation a e c.ini\nreal-ablation a f c.ini\n")
            .find("line 4: a second real-ablation a with e c.ini") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-verify pixel 10 --x=0\n")
            .find("line 3: expected 'density-verify LADDER LEVEL CHANGE SCORE'") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-verify pixel 25 --x=0 v\n")
            .find("line 3: density-verify pixel 25 does not follow its rung's record") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-verify als_qL1 10 --x=0 v\n")
            .find("line 3: density-verify als_qL1 10 does not follow") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-verify pixel 10 --x=0 v\ndensity-verify pixel 10 --x=0 v\n")
            .find("line 4: a second density-verify pixel 10") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-classify pixel 10 c.ini\n")
            .find("line 3: expected 'density-classify LADDER LEVEL CONFIG SCORE'") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-classify pixel 25 c.ini v\n")
            .find("line 3: density-classify pixel 25 does not follow its rung's record") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-classify als_qL1 10 c.ini v\n")
            .find("line 3: density-classify als_qL1 10 does not follow") != std::string::npos);
  CHECK(
      refusal(t + "density 10 0.5 s\ndensity-classify pixel 10 c.ini v\ndensity-classify pixel 10 d.ini w\n")
          .empty());
  CHECK(refusal(t + "density 10 0.5 s\ndensity-detect pixel 10 d.ini\n")
            .find("line 3: expected 'density-detect LADDER LEVEL CONFIG SCORE'") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-detect pixel 25 d.ini v\n")
            .find("line 3: density-detect pixel 25 does not follow its rung's record") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-detect pixel 10 d.ini v\ndensity-detect pixel 10 e.ini v\n")
            .find("line 4: density-detect pixel 10: v a second time") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-detect pixel 10 d.ini v\ndensity-detect pixel 10 e.ini w\n")
            .empty());
  const std::string three =
      "density 10 0.5 s\ndensity-classify pixel 10 c.ini v\ndensity-classify pixel 10 d.ini w\n"
      "density-classify pixel 10 e.ini x\n";
  CHECK(refusal(t + three).empty());
  // As many as the rung ran (no count limit, mk/density.mk's lists): a fourth is read, in order;
  // one score twice on a rung is the same record written twice.
  const std::string four = three + "density-classify pixel 10 f.ini y\n";
  CHECK(refusal(t + four).empty());
  {
    const documents::ExperimentManifest m4 = documents::parse_experiment_manifest(t + four, "experiment.txt");
    REQUIRE(m4.density.size() == 1);
    REQUIRE(m4.density[0].classify_more.size() == 4);
    CHECK(m4.density[0].classify_more[0].change == "c.ini");
    CHECK(m4.density[0].classify_more[3].change == "f.ini");
    CHECK(m4.density[0].classify_more[3].score == "y");
  }
  CHECK(refusal(t + three + "density-classify pixel 10 f.ini w\n")
            .find("line 6: density-classify pixel 10: w a second time") != std::string::npos);
  CHECK(refusal(t + "density 10 0.5 s\ndensity-verify pixel 10 --x=0 v\n").empty());
  // The two ladders rise each on its own.
  CHECK(refusal(t + "density 50 0.3 s\ndensity-sensor 10 als_qL1 s\n").empty());
  CHECK(refusal(t).empty());
}

TEST_CASE("tile list: tiles with and without noise and cover; refusals name the line") {
  const auto tiles = documents::parse_tile_list(
      "# detections truth noise cover\n"
      "a/detections.json a/truth.json 8 light\n"
      "\n"
      "b/detections.json b/truth.json 0.5\r\n"
      "c/detections.json c/truth.json  # no noise, no cover\n",
      "tiles.txt");
  REQUIRE(tiles.size() == 3);
  CHECK(tiles[0].detections == "a/detections.json");
  CHECK(tiles[0].truth == "a/truth.json");
  CHECK(tiles[0].noise_mm == 8);
  CHECK(tiles[0].cover == "light");
  CHECK(tiles[1].noise_mm == 0.5);
  CHECK(tiles[1].cover.empty());
  CHECK(std::isnan(tiles[2].noise_mm));
  CHECK(documents::write_tile_list(tiles) ==
        "a/detections.json a/truth.json 8 light\nb/detections.json b/truth.json 0.5\n"
        "c/detections.json c/truth.json\n");
  CHECK(tile_list_refusal("# nothing\n").find("lists no tiles") != std::string::npos);
  CHECK(tile_list_refusal("a b 1 c d\n").find("line 1: expected DETECTIONS TRUTH") != std::string::npos);
  CHECK(tile_list_refusal("a b\nonly\n").find("line 2: expected") != std::string::npos);
  CHECK(tile_list_refusal("a b 8mm\n").find("line 1: noise '8mm'") != std::string::npos);
  CHECK(tile_list_refusal("a b -1\n").find("noise '-1'") != std::string::npos);
  CHECK(tile_list_refusal("a b nan\n").find("noise 'nan'") != std::string::npos);
}
