// Tile recipe bounds and strictness (issue 25, round 3, cases 9, 10, 15): the pixel budget of a
// tile checked before anything renders, keys given twice, decimal numbers only, control bytes.
#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "canopy/common/error.h"
#include "rangetrace/tile.h"
#include "support/cli.h"

using namespace canopy;
using namespace canopy::rangetrace;
namespace fs = std::filesystem;

namespace {

std::string bin() { return std::string(CANOPY_BIN_DIR) + "/rangetrace"; }
fs::path data(const std::string& name) {
  return fs::path(CANOPY_SOURCE_DIR) / "tests" / "rangetrace" / "data" / "round3" / name;
}

// The message of parse_scene(text), "" when accepted.
std::string parse_error(const std::string& text, const std::string& name = "r.scene") {
  try {
    parse_scene(text, name);
  } catch (const common::Error& e) { return e.what(); }
  return "";
}

double pixels(const std::vector<TileView>& views) {
  double n = 0;
  for (const auto& v : views) n += v.pixels_x * v.pixels_y;
  return n;
}

std::vector<TileView> all_views(const Tile& t) {
  std::vector<TileView> v = tile_views(t);
  v.insert(v.begin(), canopy_view(t));
  return v;
}

}  // namespace

TEST_CASE("tile budget: the round-3 recipes are refused before rendering, naming file and line") {
  const auto dir = test::fresh_dir("rangetrace", "round3_tiles");
  struct Case {
    const char* file;
    std::string want;
  };
  const Case cases[] = {
      {"tile-80m-5mm-8lines.scene",
       "line 5: spacing 5mm: 32 images and the canopy image have 1.2e9 pixels in all (up to as many points: "
       "about "
       "215 GB of memory, 7.17 GB of frames in TMPDIR); a tile may have at most 3e7: use a spacing of at "
       "least 32mm"},
      {"tile-20m-5mm-defaults.scene", "line 3: spacing 5mm: 8 images and the canopy image have 7.6e7 pixels"},
      {"tile-100m-5mm.scene", "line 4: spacing 5mm: 8 images and the canopy image have 1.9e9 pixels"},
      {"tile-duplicate-extent.scene",
       "line 9: 'extent' is given twice, on lines 1 and 9 (a key may appear once)"},
      {"tile-origin-hex.scene", "line 9: '0x10' is not a decimal number"},
  };
  for (const auto& c : cases) {
    INFO(c.file);
    const auto out = dir / "out.las", truth = dir / "truth.json";
    std::string err;
    const auto start = std::chrono::steady_clock::now();
    const int rc = test::sh(
        bin() + " --scene " + data(c.file).string() + " -o " + out.string() + " --truth " + truth.string(),
        dir / "err.txt", &err);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    CHECK(rc == 1);  // bad data in a file (hardening.md), as every other recipe error
    CHECK_THAT(err, Catch::Contains("rangetrace: error: " + data(c.file).string() + ": " + c.want));
    CHECK(err.find("render:") == std::string::npos);  // refused while reading the recipe
    CHECK(seconds < 10);
    CHECK_FALSE(test::exists(out));
    CHECK_FALSE(test::exists(truth));
  }
  // One nadir image of 20 m at 5 mm (1.6e7 points, measured 2.8 GB) is within the bound.
  std::ifstream f(data("tile-20m-5mm-1image.scene"));
  const SceneRecipe one = parse_scene(
      std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>()), "one.scene");
  REQUIRE(one.tile);
  Tile bare;
  bare.recipe = *one.tile;
  bare.top = 0;
  const double n = pixels(all_views(bare));
  CHECK(n > 1.6e7);
  CHECK(n < kMaxTilePixels);
}

TEST_CASE("tile budget: the experiment's and the README's recipes stay within it") {
  const fs::path share = fs::path(CANOPY_SOURCE_DIR) / "share" / "scenes";
  for (const char* spacing : {"80mm", "40mm", "20mm"}) {
    std::ifstream f(share / "forest.scene");
    std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const auto at = text.find("spacing = 80mm");
    REQUIRE(at != std::string::npos);
    text.replace(at, 14, std::string("spacing = ") + spacing);
    INFO("forest.scene at " << spacing);
    CHECK(parse_error(text).empty());
  }
  // mk/scenes.mk's tile (30 m at 40 mm, rolling, two lines in two headings, fore and aft).
  CHECK(parse_error("extent = 30m\nterrain = rolling 1m 25m\ntrees = 600\nflight_lines = 2\n"
                    "headings = 0deg 90deg\nlooks = 75deg/0deg 75deg/180deg\nspacing = 40mm\n")
            .empty());
  // Just over: the forest at 15 mm.
  CHECK_THAT(parse_error("extent = 40m\nspacing = 15mm\n"), Catch::Contains("line 2: spacing 15mm"));
  // The canopy image alone.
  CHECK_THAT(
      parse_error("extent = 100m\ncanopy_spacing = 5mm\nspacing = 1m\n"),
      Catch::Contains("line 2: canopy_spacing 5mm: ") && Catch::Contains("use a canopy_spacing of at least"));
  // Defaults only: the line of the first key given that shapes the images.
  CHECK_THAT(
      parse_error("trees = 0\nlooks = 30deg/0 30deg/90deg 30deg/180deg 30deg/270deg 90deg 60deg/0 "
                  "60deg/90deg 60deg/180deg 60deg/270deg 45deg/0 45deg/90deg 45deg/180deg 45deg/270deg\n"
                  "headings = 0 30deg 60deg 90deg 120deg 150deg 180deg 210deg 240deg 270deg\n"
                  "extent = 100m\n"),
      Catch::Contains("r.scene: line 4: spacing 80mm: 260 images"));
}

TEST_CASE("tile budget: the recipe-time bound is a lower bound of the built tile's images") {
  // check_tile checks the flat, empty tile; terrain and trees only enlarge the images, and
  // run_tile checks the built tile again with the same function.
  const char* recipes[] = {
      "extent = 30m 20m\nterrain = rolling 2m 10m\ntrees = 800\nlooks = 30deg/0 75deg/180deg\nspacing = "
      "0.2m\n",
      "extent = 24m\nterrain = slope 15deg 30deg\ntrees = 300\nheadings = 45deg\nflight_lines = 3\nspacing = "
      "0.3m\n",
      "extent = 16m\ntrees = 0\nbushes = 0\nlooks = 90deg\nspacing = 0.1m\n",
  };
  for (const char* text : recipes) {
    INFO(text);
    const SceneRecipe s = parse_scene(text, "t.scene");
    REQUIRE(s.tile);
    Params p;
    p.seed = 3;
    const Tile built = build_tile(*s.tile, "t.scene", p);
    Tile bare;
    bare.recipe = *s.tile;
    bare.recipe.terrain = Terrain::kFlat;
    bare.top = 0;
    const auto real = all_views(built), lower = all_views(bare);
    REQUIRE(real.size() == lower.size());
    for (std::size_t k = 0; k < real.size(); ++k) {
      CHECK(real[k].pixels_x >= lower[k].pixels_x);
      CHECK(real[k].pixels_y >= lower[k].pixels_y);
    }
  }
  // At the limit exactly: accepted; one pixel more: refused.
  TileView canopy, scan;
  canopy.pixels_x = canopy.pixels_y = 1;
  scan.pixels_x = 10000;
  scan.pixels_y = (kMaxTilePixels - 1) / 10000;  // 2999.9999
  TileRecipe r;
  r.lines["spacing"] = 7;
  CHECK_NOTHROW(check_tile_budget({canopy, scan}, r, "x.scene"));
  scan.pixels_y = 3000;
  CHECK_THROWS_WITH(
      check_tile_budget({canopy, scan}, r, "x.scene"),
      Catch::StartsWith("x.scene: line 7: spacing 80mm: 1 image and the canopy image have 3e7"));
  // A side over 16384 pixels, within the total.
  scan.pixels_x = kMaxImageSide + 1;
  scan.pixels_y = 10;
  CHECK_THROWS_WITH(check_tile_budget({canopy, scan}, r, "x.scene"),
                    Catch::StartsWith("x.scene: line 7: an image of 16385 x 10 pixels is over 16384 a side"));
}

TEST_CASE("recipes: a key given twice is an error naming both lines") {
  CHECK_THAT(parse_error("extent = 10m\ntrees = 0\n\nextent = 20m\n"),
             Catch::Contains("r.scene: line 4: 'extent' is given twice, on lines 1 and 4"));
  CHECK_THAT(parse_error("headings = 0\nlooks = 90deg\nheadings = 90deg\n"),
             Catch::Contains("line 3: 'headings' is given twice, on lines 1 and 3"));
  CHECK_THAT(parse_error("foliage_count = 5\nviews = circle 2 75\nfoliage_count = 6\n"),
             Catch::Contains("line 3: 'foliage_count' is given twice, on lines 1 and 3"));
  // Keys that add an item may repeat.
  CHECK(parse_error("views = circle 2 75\nviews = circle 3 60\nview = 10 45\nview = 20 45\n").empty());
  CHECK(
      parse_error("extent = 20m\nvehicle = sedan 5 5 0\nvehicle = tank 15 12 0\ntree = conifer 3 15\n"
                  "tree = broadleaf 10 16\nobject = boulder 12 3 0\nobject = shed 4 12 0\nclutter = logs 1\n"
                  "clutter = fence 1\ncanopy_disc = 1 1 5 1\ncanopy_disc = 2 2 5 1\n")
          .empty());
}

TEST_CASE("recipes: numbers are decimal and finite, counts are digits") {
  struct Case {
    std::string text, want;
  };
  const Case cases[] = {
      {"origin = 0x10 0\n", "line 1: '0x10' is not a decimal number"},
      {"origin = 16abc 0\n", "line 1: '16abc' is not a decimal number"},
      {"origin = 1e999 0\n", "line 1: '1e999' is not a finite number"},
      {"origin = nan 0\n", "line 1: 'nan' is not a decimal number"},
      {"swath_overlap = 0x1p-1\n", "line 1: '0x1p-1' is not a decimal number"},
      {"trees = inf\n", "line 1: 'inf' is not a decimal number"},
      {"hide = 0x2\n", "line 1: '0x2' is not a count"},
      {"hide = +2\n", "line 1: '+2' is not a count"},
      {"hide = 2.0\n", "line 1: '2.0' is not a count"},
      {"flight_lines = 99999999999999999999\n", "line 1: count 99999999999999999999 exceeds the limit of 50"},
      {"extent = 0x10m\n", "line 1: "},
      {"views = circle 0x10 75\n", "line 1: '0x10' is not a count >= 1"},
      {"views = circle 12abc 75\n", "line 1: '12abc' is not a count >= 1"},
      {"foliage_count = 010x\nviews = circle 2 75\n", "line 1: '010x' is not a count"},
      {"foliage_radius = 1m 2m\nviews = circle 2 75\n",
       "line 1: expected 'foliage_radius = VALUE' (one value)"},
  };
  for (const auto& c : cases) {
    INFO(c.text);
    CHECK_THAT(parse_error(c.text), Catch::Contains("r.scene: " + c.want));
  }
  // Decimal forms still read.
  const SceneRecipe s =
      parse_scene("origin = +500000.5 -4.4e6 1E2\nswath_overlap = .5\nhide = 03\n", "ok.scene");
  REQUIRE(s.tile);
  CHECK(s.tile->origin.x() == 500000.5);
  CHECK(s.tile->origin.y() == -4.4e6);
  CHECK(s.tile->origin.z() == 100);
  CHECK(s.tile->swath_overlap == 0.5);
  CHECK(s.tile->hide == 3);
}

TEST_CASE("recipes: control bytes are refused and never echoed raw") {
  const std::string nul = std::string("extent = 10m\n") + '\0' + "key = 1\n";
  CHECK_THAT(parse_error(nul),
             Catch::Contains("r.scene: line 2: control byte 0x00 in column 1 (a recipe is text)"));
  CHECK_THAT(parse_error("extent = 1\x01m\n"), Catch::Contains("line 1: control byte 0x01 in column 11"));
  CHECK_THAT(parse_error("# a comment with an escape \x1b[31m\nextent = 10m\n"),
             Catch::Contains("line 1: control byte 0x1b in column 28"));
  CHECK_THAT(parse_error("extent = 10m\x7f\n"), Catch::Contains("control byte 0x7f"));
  // Tabs and CRLF line ends are text.
  CHECK(parse_error("extent =\t10m\r\ntrees = 0\r\n").empty());
  // formats/ini.h (docs/decisions/ini.md): a UTF-8 BOM is skipped; a CR inside a line is a
  // control byte; ';' is no comment in a recipe.
  CHECK(parse_error("\xEF\xBB\xBF"
                    "extent = 10m\ntrees = 0\n")
            .empty());
  CHECK_THAT(parse_error("extent = 10m\rtrees = 0\n"),
             Catch::Contains("line 1: control byte 0x0d in column 13"));
  CHECK_THAT(parse_error("extent = 10m ; x\n"), Catch::Contains("line 1: "));
  // A file name with control bytes is shown escaped.
  const std::string msg = parse_error("bogus = 1\n", std::string("r\x01\n.scene"));
  CHECK_THAT(msg, Catch::StartsWith("r\\x01\\x0a.scene: line 1: unknown key 'bogus'"));
  for (const char c : msg) CHECK(static_cast<unsigned char>(c) >= 0x20);
}
