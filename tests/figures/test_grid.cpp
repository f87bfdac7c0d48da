// tile_grid and PNG I/O (CPU only, no display): tiles land where expected, missing cells are
// drawn as "failed", trimming crops all tiles alike, labels add margins; the grid subcommand
// reads PNGs, treats '-' and missing files as failed cells and leaves no file on error.
#include <catch2/catch.hpp>

#include "canopy/common/error.h"
#include "helpers.h"

using namespace canopy;
using namespace canopy::figures;
using namespace canopy::figures::testing;

namespace {

Image solid(int w, int h, std::array<std::uint8_t, 3> c) { return Image(w, h, c); }

bool equal(const std::uint8_t* p, std::array<std::uint8_t, 3> c) {
  return p[0] == c[0] && p[1] == c[1] && p[2] == c[2];
}

const std::array<std::uint8_t, 3> kA{200, 10, 10}, kB{10, 200, 10}, kC{10, 10, 200};
const std::array<std::uint8_t, 3> kWhite{255, 255, 255}, kFailed{232, 232, 232};

}  // namespace

TEST_CASE("tile_grid places tiles row by row with gaps; a missing cell is grey and marked") {
  GridParams p;
  p.cols = 2;
  p.gap = 3;
  p.trim = false;
  p.font_size = 10;
  const int w = 60, h = 40;
  const Image out = tile_grid({solid(w, h, kA), solid(w, h, kB), std::nullopt, solid(w, h, kC)}, p);
  REQUIRE(out.width == 2 * w + 3 * p.gap);
  REQUIRE(out.height == 2 * h + 3 * p.gap);
  // Every pixel of every present tile, and the gaps.
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      CHECK(equal(out.at(3 + x, 3 + y), kA));
      CHECK(equal(out.at(3 + w + 3 + x, 3 + y), kB));
      CHECK(equal(out.at(3 + w + 3 + x, 3 + h + 3 + y), kC));
    }
  }
  for (int y = 0; y < out.height; ++y) {
    CHECK(equal(out.at(0, y), kWhite));
    CHECK(equal(out.at(3 + w + 1, y), kWhite));
  }
  // The failed cell: grey corners, dark text in the middle, nothing spilled outside it.
  const int fx = 3, fy = 3 + h + 3;
  CHECK(equal(out.at(fx, fy), kFailed));
  CHECK(equal(out.at(fx + w - 1, fy + h - 1), kFailed));
  int dark = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) dark += out.at(fx + x, fy + y)[0] < 128;
  }
  CHECK(dark > 10);
}

TEST_CASE("tile_grid trims every tile to the union of the content boxes") {
  Image a = solid(40, 30, kWhite), b = solid(40, 30, kWhite);
  for (int y = 5; y <= 9; ++y) {
    for (int x = 10; x <= 19; ++x) std::copy(kA.begin(), kA.end(), a.at(x, y));
  }
  for (int y = 8; y <= 14; ++y) {
    for (int x = 15; x <= 24; ++x) std::copy(kB.begin(), kB.end(), b.at(x, y));
  }
  GridParams p;
  p.cols = 2;
  p.gap = 0;
  p.margin = 2;
  const Image out = tile_grid({a, b}, p);
  // Union [10, 24] x [5, 14] plus 2 pixels: 19 x 14 per tile.
  REQUIRE(out.width == 2 * 19);
  REQUIRE(out.height == 14);
  CHECK(equal(out.at(2, 2), kA));  // a's content starts at (10, 5) -> (2, 2)
  CHECK(equal(out.at(1, 2), kWhite));
  CHECK(equal(out.at(19 + 7, 5), kB));    // b's (15, 8) -> (7, 5) in the second tile
  CHECK(equal(out.at(19 + 16, 11), kB));  // b's (24, 14) -> (16, 11)
  CHECK(equal(out.at(19 + 17, 12), kWhite));
}

TEST_CASE("tile_grid labels add a left and a top margin holding text") {
  GridParams p;
  p.cols = 2;
  p.trim = false;
  const std::vector<std::optional<Image>> cells{solid(50, 50, kA), solid(50, 50, kB)};
  const Image plain = tile_grid(cells, p);
  p.row_labels = {"sedan"};
  p.col_labels = {"0 mm", "32 mm"};
  const Image labelled = tile_grid(cells, p);
  const int left = labelled.width - plain.width, top = labelled.height - plain.height;
  REQUIRE(left > 20);
  REQUIRE(top > 10);
  auto dark_in = [&](int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) n += labelled.at(x, y)[0] < 100 && labelled.at(x, y)[1] < 100;
    }
    return n;
  };
  CHECK(dark_in(0, top, left, labelled.height) > 10);  // row label
  CHECK(dark_in(left, 0, labelled.width, top) > 10);   // column labels
  CHECK(equal(labelled.at(left + p.gap, top + p.gap), kA));

  p.row_labels = {"a", "b"};
  CHECK_THROWS_AS(tile_grid(cells, p), common::UsageError);
  p.row_labels.clear();
  p.col_labels = {"only one"};
  CHECK_THROWS_AS(tile_grid(cells, p), common::UsageError);
  p.col_labels.clear();
  CHECK_THROWS_AS(tile_grid({std::nullopt, std::nullopt}, p), common::Error);
}

TEST_CASE("PNG round trip keeps every pixel and encodes deterministically") {
  Image im(7, 5);
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 7; ++x) {
      im.at(x, y)[0] = static_cast<std::uint8_t>(30 * x);
      im.at(x, y)[1] = static_cast<std::uint8_t>(50 * y);
      im.at(x, y)[2] = static_cast<std::uint8_t>(x * y);
    }
  }
  const fs::path dir = fresh_dir("png");
  write_png(im, (dir / "a.png").string());
  const Image back = read_png((dir / "a.png").string());
  REQUIRE(back.width == 7);
  REQUIRE(back.height == 5);
  CHECK(back.rgb == im.rgb);
  CHECK(encode_png(im) == slurp(dir / "a.png"));
  CHECK(count_files(dir) == 1);
  std::ofstream(dir / "junk.png") << "not a png";
  CHECK_THROWS_AS(read_png((dir / "junk.png").string()), common::DataError);
  CHECK_THROWS_AS(read_png((dir / "absent.png").string()), common::DataError);
}

TEST_CASE("figures grid: '-' and missing files are failed cells; errors leave no output") {
  const fs::path dir = fresh_dir("grid_cli");
  write_png(solid(30, 20, kA), (dir / "a.png").string());
  write_png(solid(30, 20, kB), (dir / "b.png").string());
  std::string err;
  const std::string out = (dir / "grid.png").string();
  REQUIRE(sh(kBin + " grid --no-trim --gap 2 --cols 2 -o " + out + " " + (dir / "a.png").string() + " - " +
                 (dir / "gone.png").string() + " " + (dir / "b.png").string(),
             dir / "err", &err) == 0);
  CHECK(err.find("gone.png") != std::string::npos);
  const Image g = read_png(out);
  REQUIRE(g.width == 2 * 30 + 3 * 2);
  REQUIRE(g.height == 2 * 20 + 3 * 2);
  CHECK(equal(g.at(2, 2), kA));
  CHECK(equal(g.at(2 + 30 + 2, 2), kFailed));  // '-'
  CHECK(equal(g.at(2, 2 + 20 + 2), kFailed));  // missing file
  CHECK(equal(g.at(2 + 30 + 2 + 29, 2 + 20 + 2 + 19), kB));

  // Labels: whitespace-separated without commas (Makefile lists), comma-separated otherwise.
  const std::string two = (dir / "a.png").string() + " - - " + (dir / "b.png").string();
  CHECK(sh(kBin + " grid --cols 2 --labels-row 'sedan tank' --labels-col '0 mm,2 mm' -o " + out + " " + two,
           dir / "err", &err) == 0);
  CHECK(read_png(out).width > g.width);
  CHECK(sh(kBin + " grid --cols 2 --labels-row 'sedan tank semi' -o " + out + " " + two, dir / "err", &err) ==
        2);
  CHECK(sh(kBin + " grid --cols 2 --labels-col '0 mm 2 mm' -o " + out + " " + two, dir / "err", &err) == 2);

  fs::remove(out);
  std::ofstream(dir / "bad.png") << "garbage";
  CHECK(sh(kBin + " grid --cols 2 -o " + out + " " + (dir / "a.png").string() + " " + (dir / "bad.png").string(),
           dir / "err", &err) == 1);
  CHECK(err.find("bad.png") != std::string::npos);
  CHECK(sh(kBin + " grid --cols 2 -o " + out + " - -", dir / "err", &err) == 1);
  CHECK(sh(kBin + " grid --cols 2 --labels-row a,b,c -o " + out + " " + (dir / "a.png").string(), dir / "err",
           &err) == 2);
  CHECK_FALSE(fs::exists(out));
  CHECK(count_files(dir) == 4);  // a.png b.png bad.png err: no temporaries
}

TEST_CASE("figures parameters out of range name their option") {
  CHECK_NOTHROW(validate(MeshView{}));
  CHECK_NOTHROW(validate(GridParams{}));
  CHECK_NOTHROW(validate(PlotParams{}));
  MeshView mv;
  mv.width = 15;
  CHECK_THROWS_WITH(validate(mv), Catch::Contains("--width/--height"));
  mv = {};
  mv.elevation_deg = 90;
  CHECK_THROWS_WITH(validate(mv), Catch::Contains("--elevation"));
  mv = {};
  mv.box[2] = 0;
  CHECK_THROWS_WITH(validate(mv), Catch::Contains("--box-height"));
  GridParams gp;
  gp.cols = 0;
  CHECK_THROWS_WITH(validate(gp), Catch::Contains("--cols"));
  gp = {};
  gp.font_size = 201;
  CHECK_THROWS_WITH(validate(gp), Catch::Contains("--font-size"));
  gp = {};
  gp.gap = -1;
  CHECK_THROWS_WITH(validate(gp), Catch::Contains("--gap"));
  gp = {};
  gp.margin = 1001;
  CHECK_THROWS_AS(validate(gp), common::UsageError);
  PlotParams pp;
  pp.height = 8193;
  CHECK_THROWS_WITH(validate(pp), Catch::Contains("--width/--height"));
}
