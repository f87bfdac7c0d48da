// rangetrace as a stage (stage.h): parameter checks naming the options, the order in which a
// request that cannot be rendered is refused, and run()'s outputs against the functions it
// composes (real POV-Ray renders of small images).
#include <catch2/catch.hpp>

#include <fstream>
#include <string>

#include "canopy/common/error.h"
#include "canopy/formats/pcd.h"
#include "rangetrace/stage.h"
#include "support/cli.h"

using namespace canopy;
using namespace canopy::rangetrace;

namespace {

// A tile recipe of hand-placed content only (no vehicle: nothing to parse with POV-Ray).
std::string tile_recipe(const std::filesystem::path& dir) {
  const std::string path = (dir / "tile.scene").string();
  std::ofstream(path) << "extent = 10m\ntrees = 0\nbushes = 0\nflight_lines = 1\n";
  return path;
}

std::string single_recipe(const std::filesystem::path& dir) {
  const std::string path = (dir / "three.scene").string();
  std::ofstream(path) << "view = 20deg 75deg\nview = 140deg 60deg\nview = 260deg 70deg\n";
  return path;
}

Params small() {
  Params p;
  p.size = 64;
  p.spacing = 0.12;  // a 7.7 m field
  p.seed = 5;
  return p;
}

}  // namespace

TEST_CASE("stage: validate names the options of sizes out of range") {
  Params p;
  CHECK_NOTHROW(validate(p));
  // Each message names the one option at fault (and the size given), not every bound at once
  // ("need 8 <= --size <= 8192, --spacing > 0 and crop sizes > 0" was the answer to all).
  for (int size : {7, 8193}) {
    p.size = size;
    CHECK_THROWS_WITH(validate(p), "--size must be in [8, 8192] pixels (given " + std::to_string(size) + ")");
  }
  p.size = 8;
  CHECK_NOTHROW(validate(p));
  p.spacing = 0;
  CHECK_THROWS_WITH(validate(p), "--spacing must be > 0");
  p.spacing = 0.03;
  p.crop_height = -1;
  CHECK_THROWS_WITH(validate(p), "--crop-height must be > 0");
  p.crop_height = 4;
  p.crop_width = 0;
  CHECK_THROWS_WITH(validate(p), "--crop-width must be > 0");
}

TEST_CASE("stage: load_inputs refuses what cannot be rendered, naming the option") {
  const auto dir = test::fresh_dir("rangetrace", "stage-inputs");
  const std::string tile = tile_recipe(dir), single = single_recipe(dir);
  auto refused = [](const Request& r) {
    try {
      (void)load_inputs(r);
    } catch (const common::UsageError& e) { return std::string(e.what()); }
    return std::string("accepted");
  };
  Request r;
  CHECK_THAT(refused(r), Catch::Contains("--model is required"));
  r.scene = tile;
  r.model = "sedan";
  CHECK_THAT(refused(r), Catch::Contains("--model: the tile scene"));
  r.model.clear();
  r.truth = true;  // a tile writes its truth
  const Inputs t = load_inputs(r);
  CHECK(t.tile());
  CHECK_FALSE(t.model);
  r.scene = single;
  CHECK_THAT(refused(r), Catch::Contains("--model is required"));  // before --truth
  r.model = "sedan";
  CHECK_THAT(refused(r), Catch::Contains("--truth: only tile scenes"));
  r.truth = false;
  const Inputs s = load_inputs(r);
  CHECK_FALSE(s.tile());
  REQUIRE(s.scene);
  CHECK(s.scene->views.size() == 3);
  CHECK(s.model->name == "sedan");
  r.scene.clear();
  CHECK_THAT(refused(r), Catch::Contains("--scene is required for a scan"));
  r.picture = true;  // the model alone
  const Inputs m = load_inputs(r);
  CHECK_FALSE(m.scene);
  CHECK(m.model);
}

TEST_CASE("stage: run's scan is render_scan's, with the family class as a note") {
  const auto dir = test::fresh_dir("rangetrace", "stage-run");
  Request r;
  r.model = "family:pickup:3";
  r.scene = single_recipe(dir);
  const Inputs in = load_inputs(r);
  Params p = small();
  p.threads = 3;  // one POV-Ray process per view
  const Outputs out = run(p, in);
  REQUIRE_FALSE(out.cloud.empty());
  CHECK(out.cloud.comments.empty());
  CHECK(out.notes == std::vector<std::string>{"class pickup"});
  CHECK_FALSE(out.tile);
  CHECK(out.picture.empty());
  CHECK(out.summary == std::to_string(out.cloud.size()) + " points (" + in.model->name + ", " +
                           in.scene->name + ", 3 views)");
  p.threads = 1;
  CHECK(formats::serialize_pcd(out.cloud) == formats::serialize_pcd(render_scan(*in.model, *in.scene, p)));
  p.size = 4;
  CHECK_THROWS_AS(run(p, in), common::UsageError);
}
