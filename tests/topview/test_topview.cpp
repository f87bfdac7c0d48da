// topview: hand-placed scans and footprints; pixel colours checked where the heights, the
// outlines and the scale bar must be.
#include <png.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/formats/pcd.h"
#include "support/cli.h"
#include "topview/topview.h"

using namespace canopy;
using Json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

// 10 x 10 m of ground, one point at the centre of every 0.05 m square of [0, 10]^2 (400 points
// a m², 100 occupied 1 m cells), z = base + slope * x, with a 2 x 2 m box over [4, 6]^2 whose
// top is `box` m above the ground; shifted to UTM coordinates.
const double E = 500000, N = 5400000;
formats::PointCloud scan(double box = 2.0, double slope = 0, double base = 0) {
  formats::PointCloud pc;
  auto& x = pc.add("x", formats::kFloat64);
  auto& y = pc.add("y", formats::kFloat64);
  auto& z = pc.add("z", formats::kFloat64);
  for (int i = 0; i < 200; ++i) {
    for (int j = 0; j < 200; ++j) {
      const double px = 0.025 + i * 0.05, py = 0.025 + j * 0.05;
      x.push_back(E + px);
      y.push_back(N + py);
      z.push_back(base + slope * px + (px > 4 && px < 6 && py > 4 && py < 6 ? box : 0.0));
    }
  }
  pc.resize(x.size());
  return pc;
}

topview::Ring rect(double ax, double ay, double bx, double by) {
  return {{E + ax, N + ay}, {E + bx, N + ay}, {E + bx, N + by}, {E + ax, N + by}};
}

topview::Footprints shapes(std::vector<topview::Shape> s) {
  topview::Footprints f;
  f.shapes = std::move(s);
  return f;
}

// Pixel (col, row) of tile point (x, y).
std::pair<int, int> px(const topview::Image& img, double x, double y) {
  return {static_cast<int>((E + x - img.x0) / img.pixel), static_cast<int>((img.y1 - (N + y)) / img.pixel)};
}

topview::Rgb at(const topview::Image& img, double x, double y) {
  const auto [c, r] = px(img, x, y);
  return img.at(c, r);
}

int distance(const topview::Rgb& a, const topview::Rgb& b) {
  int d = 0;
  for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(a[k] - b[k]));
  return d;
}

// Does a pixel within `reach` rows and columns of (x, y) have colour c?
bool near(const topview::Image& img, double x, double y, const topview::Rgb& c, int reach = 1) {
  const auto [col, row] = px(img, x, y);
  for (int r = row - reach; r <= row + reach; ++r) {
    for (int k = col - reach; k <= col + reach; ++k) {
      if (k >= 0 && r >= 0 && k < img.map_width && r < img.map_height && img.at(k, r) == c) return true;
    }
  }
  return false;
}

std::string write_json(const fs::path& p, const Json& j) {
  std::ofstream(p.string()) << j.dump();
  return p.string();
}

Json footprint(const topview::Ring& r) {
  Json a = Json::array();
  for (const auto& p : r) a.push_back({p[0], p[1]});
  return a;
}

struct Png {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  topview::Rgb at(int c, int r) const {
    const std::size_t i = 3 * (static_cast<std::size_t>(r) * width + c);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

Png read_png(const fs::path& p) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  REQUIRE(png_image_begin_read_from_file(&png, p.string().c_str()) != 0);
  png.format = PNG_FORMAT_RGB;
  Png out;
  out.rgb.resize(PNG_IMAGE_SIZE(png));
  REQUIRE(png_image_finish_read(&png, nullptr, out.rgb.data(), 0, nullptr) != 0);
  out.width = static_cast<int>(png.width);
  out.height = static_cast<int>(png.height);
  return out;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p.string(), std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("height colour: the viridis ramp from 0 to 3 m, clamped") {
  CHECK(topview::height_colour(0) == topview::Rgb{68, 1, 84});
  CHECK(topview::height_colour(-2) == topview::Rgb{68, 1, 84});
  CHECK(topview::height_colour(1.5) == topview::Rgb{33, 145, 140});
  CHECK(topview::height_colour(3) == topview::Rgb{253, 231, 37});
  CHECK(topview::height_colour(30) == topview::Rgb{253, 231, 37});
  CHECK(topview::height_colour(0.375) == topview::Rgb{64, 42, 112});  // halfway between the first two stops
}

TEST_CASE("render: a 1.5 m box on flat ground reads 1.5 m, the ground 0, whatever the ground's height") {
  for (const double base : {0.0, 312.4}) {
    INFO("ground at z = " << base);
    const topview::Image img = topview::render(scan(1.5, 0, base), {}, {});
    // 400 points a m²: data pixel sqrt(2 / 400) = 0.0707 -> 0.07 m; 9.95 m / 0.07 = 142.1 -> 144
    // data pixels, zoomed 7 times (1000 / 143.1 -> 7): 0.01 m map pixels, 1008 of them.
    CHECK(img.density == Approx(400));
    CHECK(img.zoom == 7);
    CHECK(img.pixel == Approx(0.01));
    CHECK(img.map_width == 1008);
    CHECK(img.map_height == 1008);
    CHECK(img.width > img.map_width);  // the legend on the right
    CHECK(at(img, 5, 5) == topview::height_colour(1.5));
    CHECK(at(img, 4.5, 5.5) == topview::height_colour(1.5));
    CHECK(at(img, 8, 8) == topview::height_colour(0));
    CHECK(at(img, 1, 2) == topview::height_colour(0));
    // North is up, east right: the box's south-west corner is left of and below its north-east one.
    CHECK(px(img, 4, 4).second > px(img, 6, 6).second);
    CHECK(px(img, 4, 4).first < px(img, 6, 6).first);
  }
}

TEST_CASE("legend: the pixel it states is the data pixel (one height value), not the zoomed map pixel") {
  // 400 points a m²: 0.07 m data pixels drawn 7 x 7 (0.01 m map pixels, as above). The legend
  // said "pixel 0.010 m", a resolution the heights do not have (a real plot at 13.5 points/m²:
  // "pixel 0.076 m" for 0.38 m cells).
  const topview::Image img = topview::render(scan(1.5, 0, 0), {}, {});
  REQUIRE(img.zoom == 7);
  const std::vector<std::string> text = topview::legend_text({}, img);
  CHECK(std::count(text.begin(), text.end(), "pixel 0.070 m") == 1);
  CHECK(std::count(text.begin(), text.end(), "pixel 0.010 m") == 0);
  CHECK(std::count(text.begin(), text.end(), "400.0 points/m2") == 1);
  // A given --pixel is what the legend states, whatever the zoom.
  topview::Params p;
  p.pixel = 0.25;
  const topview::Image given = topview::render(scan(1.5, 0, 0), {}, p);
  REQUIRE(given.zoom > 1);
  const std::vector<std::string> t2 = topview::legend_text({}, given);
  CHECK(std::count(t2.begin(), t2.end(), "pixel 0.25 m") == 1);
}

TEST_CASE("render: on a 10% slope the ground still reads about 0 and the box about 1.5 m") {
  const topview::Image img = topview::render(scan(1.5, 0.1, 50), {}, {});
  // The lowest point of a 1 m cell lies 0.05 m below its centre on this slope: within 0.1 m.
  for (const auto& [x, y] : {std::pair{1.0, 1.0}, {8.5, 8.5}, {2.3, 7.7}}) {
    INFO(x << ", " << y);
    CHECK(distance(at(img, x, y), topview::height_colour(0)) <=
          distance(topview::height_colour(0.1), topview::height_colour(0)));
  }
  CHECK(distance(at(img, 5, 5), topview::height_colour(1.5)) <=
        distance(topview::height_colour(1.6), topview::height_colour(1.5)));
}

TEST_CASE(
    "render: --size keeps its meaning (pixels along the longer side, no zoom); --pixel sets the data pixel") {
  const topview::Image sized = topview::render(scan(), {}, {100, 0, 0});
  CHECK(sized.pixel == Approx(0.0995));
  CHECK(sized.zoom == 1);
  CHECK(sized.map_width == 101);
  const topview::Image pixel = topview::render(scan(), {}, {0, 0.25, 0});
  CHECK(pixel.pixel * pixel.zoom == Approx(0.25));
  CHECK(pixel.zoom == 8);  // 9.95 / 0.25 = 39.8 -> 41 data pixels, 1000 / 40.8 > 8: at most 8
  CHECK(pixel.map_width == 41 * 8);
  CHECK(at(pixel, 5, 5) == topview::height_colour(2.0));
}

TEST_CASE(
    "render: empty pixels between sparse points are filled, beyond the reach of the fill stay no-data") {
  // A 1 m grid of points (1 a m²): pixel sqrt(2) -> 1.41 m, every pixel near a point.
  formats::PointCloud pc;
  auto& x = pc.add("x", formats::kFloat64);
  auto& y = pc.add("y", formats::kFloat64);
  auto& z = pc.add("z", formats::kFloat64);
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 40; ++j) {
      if (i >= 10 && i < 30 && j >= 10 && j < 30) continue;  // a 20 m hole (a pond)
      x.push_back(E + i + 0.5);
      y.push_back(N + j + 0.5);
      z.push_back(0);
    }
  }
  pc.resize(x.size());
  // At 0.1 m pixels the 9 empty pixels between two points are closed by the fill (8 passes,
  // one pixel a pass from each side); the pond's middle, 100 pixels from a point, is not.
  const topview::Image img = topview::render(pc, {}, {0, 0.1, 0});
  CHECK(at(img, 5, 5.5) == topview::height_colour(0));  // between points
  CHECK(at(img, 20, 20) == topview::kNoData);           // the pond's middle
}

TEST_CASE("render: outlines in their kind's colour on the footprint's edges, not inside; thin for rejected") {
  const topview::Footprints f = shapes({{rect(1, 1, 3, 2), topview::Kind::cls},
                                        {rect(6.5, 1, 8.5, 2), topview::Kind::model},
                                        {rect(1, 7, 3, 8), topview::Kind::rejected},
                                        {rect(6.5, 7, 8.5, 8), topview::Kind::failed},
                                        {rect(4.2, 7, 5.8, 8), topview::Kind::none}});
  const topview::Image img = topview::render(scan(), f, {});
  CHECK(at(img, 2, 1) == topview::kClass);              // bottom edge
  CHECK(at(img, 3, 1.5) == topview::kClass);            // right edge
  CHECK(at(img, 2, 1.5) == topview::height_colour(0));  // inside: not filled
  CHECK(at(img, 7.5, 2) == topview::kModel);
  CHECK(at(img, 7.5, 7) == topview::kFailed);
  CHECK(near(img, 2, 7, topview::kRejected));
  CHECK(near(img, 5, 8, topview::kNone));
  // A border of black beside the thick outlines, none beside the thin ones.
  const auto [c, r] = px(img, 2, 1);
  CHECK((img.at(c, r + 2) == topview::Rgb{0, 0, 0} || img.at(c, r - 2) == topview::Rgb{0, 0, 0}));
  const auto [c2, r2] = px(img, 2, 7);
  for (int d = -3; d <= 3; ++d) CHECK(img.at(c2, r2 + d) != topview::Rgb{0, 0, 0});
  // The legend lists every candidate kind (swatches in the panel), not the score's.
  auto in_panel = [&](const topview::Rgb& colour) {
    for (int rr = 0; rr < img.height; ++rr) {
      for (int cc = img.map_width; cc < img.width; ++cc) {
        if (img.at(cc, rr) == colour) return true;
      }
    }
    return false;
  };
  for (const auto& colour :
       {topview::kModel, topview::kClass, topview::kNone, topview::kRejected, topview::kFailed})
    CHECK(in_panel(colour));
  CHECK_FALSE(in_panel(topview::kWrong));
  CHECK_FALSE(in_panel(topview::kTruth));  // no truth given
}

TEST_CASE("render: the scale bar is a round length, as many pixels as it is long") {
  const topview::Image img = topview::render(scan(), {}, {});
  // Text scale 2 (a 1008-pixel map): the bar may take 240 pixels = 2.4 m at 0.01 m: 2 m.
  CHECK(img.bar_metres == Approx(2.0));
  CHECK(img.bar_pixels == 200);
  int run = 0;
  while (img.bar_col + run < img.width && img.at(img.bar_col + run, img.bar_row) == topview::Rgb{0, 0, 0})
    ++run;
  CHECK(run == 200);
  CHECK(img.at(img.bar_col - 1, img.bar_row) != topview::Rgb{0, 0, 0});
  // Without the legend: the map alone, no bar.
  topview::Params bare;
  bare.legend = false;
  const topview::Image map = topview::render(scan(), {}, bare);
  CHECK(map.width == map.map_width);
  CHECK(map.height == map.map_height);
  CHECK(map.bar_pixels == 0);
  // At --size 100 (0.0995 m pixels, text scale 1: 120 pixels = 11.9 m): 10 m = 101 pixels.
  const topview::Image small = topview::render(scan(), {}, {100, 0, 0});
  CHECK(small.bar_metres == Approx(10.0));
  CHECK(small.bar_pixels == 101);
}

TEST_CASE("render: a picture beyond the bound is refused when the pixel is given, coarsened when not") {
  // A footprint 30 km away widens the box: at 0.005 m that would be 6 million pixels a side.
  const topview::Footprints far = shapes({{rect(30000, 0, 30002, 1), topview::Kind::model}});
  CHECK_THROWS_AS(topview::render(scan(), far, {0, 0.005, 0}), common::UsageError);
  CHECK_THROWS_AS(topview::render(scan(), {}, {8192, 0, 0}), common::UsageError);  // 8193 x 8193 + legend
  // A footprint at 1e19 m, a stray point 2000 km away: drawn within the bound (the ground's
  // cells coarsened), not a failed allocation.
  const topview::Footprints huge = shapes({{rect(1e19, 0, 1e19 + 2, 1), topview::Kind::model}});
  formats::PointCloud stray = scan();
  stray.col("x").push_back(E + 2e6);
  stray.col("y").push_back(N + 2e6);
  stray.col("z").push_back(0);
  stray.resize(stray.col("x").size());
  for (const auto& [pc, fp] : {std::pair{scan(), huge}, {stray, topview::Footprints{}}}) {
    const topview::Image i = topview::render(pc, fp, {});
    CHECK(i.width <= topview::kMaxSide);
    CHECK(i.height <= topview::kMaxSide);
  }
  const topview::Image img = topview::render(scan(), far, {});
  CHECK(img.width <= topview::kMaxSide);
  CHECK(static_cast<long long>(img.width) * img.height <= topview::kMaxPixels);
  CHECK(img.zoom == 1);
}

TEST_CASE("the font has every character of the legend") {
  std::vector<std::string> texts{"^ north up",
                                 "height above ground (m)",
                                 "outlines (count)",
                                 "no point",
                                 "pixel 0.093 m",
                                 "24.8 points/m2",
                                 "too_sparse vegetation_like not given 3+"};
  for (int k = 0; k < topview::kKinds; ++k) texts.push_back(topview::label_of(static_cast<topview::Kind>(k)));
  auto bitmap = [](char c) {
    std::string b;
    for (int r = 0; r < topview::kGlyphHeight; ++r) {
      for (int col = 0; col < topview::kGlyphWidth; ++col) b += topview::glyph_ink(c, col, r) ? '#' : '.';
    }
    return b;
  };
  for (const std::string& t : texts) {
    for (const char c : t) {
      INFO("'" << c << "' in \"" << t << "\"");
      CHECK(bitmap(c) != bitmap('?'));
    }
  }
  CHECK(bitmap(' ') == std::string(topview::kGlyphWidth * topview::kGlyphHeight, '.'));
  CHECK(bitmap('1') != bitmap('l'));
}

TEST_CASE("topview reads detections v1 and v2, rejected candidates from the index by reason") {
  const fs::path dir = test::fresh_dir("topview", "levels");
  // A 2 m x 1 m candidate at (x, y), its long side along the heading (0 or 90 degrees).
  auto candidate = [](const char* id, double x, double y, bool turned) {
    const double c = turned ? 0 : 1, s = turned ? 1 : 0;
    return Json{{"id", id},
                {"transform", {{c, -s, 0, x}, {s, c, 0, y}, {0, 0, 1, 0}, {0, 0, 0, 1}}},
                {"centre", {x, y, 0}},
                {"length", 2},
                {"width", 1},
                {"heading", turned ? 1.5707963267948966 : 0}};
  };
  const Json index{{"format", "canopy.candidates"},
                   {"version", 1},
                   {"candidates",
                    {candidate("c1", E + 2, N + 1.5, false), candidate("c2", E + 7.5, N + 2, true),
                     candidate("c3", E + 2, N + 8, false), candidate("c4", E + 8, N + 8, false)}}};
  fs::create_directories(dir / "cands");
  write_json(dir / "cands" / "index.json", index);
  const Json v1{
      {"format", "canopy.detections"},
      {"version", 1},
      {"index", "cands/index.json"},
      {"detections", {{{"candidate", "c1"}, {"model", "sedan"}, {"footprint", footprint(rect(1, 1, 3, 2))}}}},
      {"rejected",
       {{{"candidate", "c3"}, {"reason", "none"}, {"confidence", 0.8}},
        {{"candidate", "c4"}, {"reason", "failed"}, {"confidence", nullptr}}}}};
  // As written by collect run from the directory above: the index path is relative to the
  // detections' directory here, found there.
  const std::string d1 = write_json(dir / "v1.json", v1);
  topview::Footprints f = topview::read_footprints({d1, "", "", ""}, 0);
  REQUIRE(f.shapes.size() == 3);
  CHECK(f.shapes[0].kind == topview::Kind::none);
  CHECK(f.shapes[1].kind == topview::Kind::failed);
  CHECK(f.shapes[2].kind == topview::Kind::model);
  CHECK(f.shapes[0].ring[0][0] == Approx(E + 3));  // c3: centre 2, half length 1, heading 0
  CHECK(f.shapes[0].ring[0][1] == Approx(N + 7.5));
  CHECK(f.undrawn == 0);

  Json v2 = v1;
  v2["version"] = 2;
  v2["detections"][0]["level"] = "class";
  v2["detections"][0]["model"] = nullptr;
  v2["detections"][0]["class"] = "car";
  v2["rejected"].push_back({{"candidate", "c2"}, {"reason", "too_sparse"}, {"detail", "3 points"}});
  const std::string d2 = write_json(dir / "v2.json", v2);
  f = topview::read_footprints({d2, "", "", ""}, 0);
  REQUIRE(f.shapes.size() == 4);
  CHECK(f.shapes[3].kind == topview::Kind::cls);
  CHECK(f.shapes[2].kind == topview::Kind::rejected);
  CHECK(f.reasons == std::map<std::string, int>{{"too_sparse", 1}});
  // Many reasons (the input's text): the legend lists 8 and sums the rest, and stays in the
  // bound.
  topview::Footprints many = f;
  for (int k = 0; k < 5000; ++k) many.reasons["reason_" + std::to_string(k)] = 1;
  const topview::Image listed = topview::render(scan(), many, {});
  CHECK(listed.height == listed.map_height);  // not taller than the 1008-pixel map
  // c2 turned by 90°: its long side along y.
  double ymin = 1e18, ymax = -1e18;
  for (const auto& p : f.shapes[2].ring) ymin = std::min(ymin, p[1]), ymax = std::max(ymax, p[1]);
  CHECK(ymax - ymin == Approx(2));

  // Drawn: the class colour on the detection's edge, the rejected one's outline where the
  // index puts it.
  const topview::Image img = topview::render(scan(), f, {});
  CHECK(at(img, 2, 1) == topview::kClass);
  CHECK(near(img, 7, 2, topview::kRejected));  // c2's west edge at x = 7.5 - 0.5
  CHECK(at(img, 7.5, 2) == topview::height_colour(0));

  // No index to be found: drawn without the rejected ones, counted.
  Json lost = v2;
  lost["index"] = "elsewhere/index.json";
  f = topview::read_footprints({write_json(dir / "lost.json", lost), "", "", ""}, 0);
  CHECK(f.shapes.size() == 1);
  CHECK(f.undrawn == 3);
  // --index given: used.
  f = topview::read_footprints(
      {write_json(dir / "lost.json", lost), "", "", (dir / "cands" / "index.json").string()}, 0);
  CHECK(f.shapes.size() == 4);

  // Bad input, the file and the member named.
  struct Bad {
    Json doc;
    std::string file, message;
  };
  Json bad_level = v2, bad_reason = v2, bad_version = v2, unknown = v2, no_centre = index;
  bad_level["detections"][0]["level"] = "part";
  bad_reason["rejected"][0]["reason"] = 3;
  bad_version["version"] = 3;
  unknown["rejected"][0]["candidate"] = "c9";
  no_centre["candidates"][2].erase("centre");
  const std::vector<Bad> bad{
      {bad_level, d2, "detections[0].level must be model or class, not \"part\""},
      {bad_reason, d2, "rejected[0].reason must be a string, not 3"},
      {bad_version, d2, "version 3"},
      {unknown, (dir / "cands" / "index.json").string(), "has no candidate \"c9\""},
  };
  for (const auto& b : bad) {
    INFO(b.message);
    write_json(dir / "v2.json", b.doc);
    try {
      topview::read_footprints({d2, "", "", ""}, 0);
      FAIL("accepted");
    } catch (const common::DataError& e) {
      CHECK(e.file() == b.file);
      CHECK_THAT(e.what(), Catch::Contains(b.message));
    }
  }
  write_json(dir / "v2.json", v2);
  write_json(dir / "cands" / "index.json", no_centre);
  CHECK_THROWS_WITH(topview::read_footprints({d2, "", "", ""}, 0),
                    Catch::Contains("candidates[2]: missing \"centre\""));
}

TEST_CASE("topview CLI: outcome colours from a score, missed vehicles in yellow, same bytes twice") {
  const fs::path dir = test::fresh_dir("topview", "cli");
  formats::write_pcd(scan(), (dir / "scan.pcd").string());
  const Json det{{"format", "canopy.detections"},
                 {"version", 1},
                 {"detections", {{{"candidate", "c1"}, {"footprint", footprint(rect(1, 1, 3, 2))}}}}};
  const Json truth{{"format", "canopy.scene_truth"},
                   {"version", 1},
                   {"vehicles",
                    {{{"instance", 1}, {"footprint", footprint(rect(1.1, 1.1, 2.9, 1.9))}},
                     {{"instance", 2}, {"footprint", footprint(rect(7, 7, 9, 8))}}}}};
  const Json score{{"format", "canopy.scene_score"},
                   {"version", 1},
                   {"tiles", {Json::object()}},
                   {"matches",
                    {{{"tile", 0}, {"candidate", "c1"}, {"outcome", "wrong"}, {"instance", 1}},
                     {{"tile", 0}, {"candidate", nullptr}, {"outcome", "missed"}, {"instance", 2}}}}};
  write_json(dir / "d.json", det);
  write_json(dir / "t.json", truth);
  write_json(dir / "s.json", score);
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/topview";
  const std::string args = " -q -i " + (dir / "scan.pcd").string() + " --detections " +
                           (dir / "d.json").string() + " --truth " + (dir / "t.json").string() + " --score " +
                           (dir / "s.json").string();
  std::string err;
  REQUIRE(test::sh(bin + args + " --size 200 -o " + (dir / "top.png").string(), dir / "err.txt", &err) == 0);
  const Png png = read_png(dir / "top.png");
  auto at = [&](double x, double y) {  // 0.04975 m pixels from (0.025, 9.975) at the top left
    return png.at(static_cast<int>((x - 0.025) / 0.04975), static_cast<int>((9.975 - y) / 0.04975));
  };
  CHECK(png.width == 201 + 232);         // the map, the legend at text scale 1: (2 x 8 + 36 x 6) pixels
  CHECK(png.height >= 201);              // the legend may be taller than the map
  CHECK(at(2, 1) == topview::kWrong);    // the detection, wrong model
  CHECK(at(8, 7) == topview::kMissed);   // the missed vehicle
  CHECK(at(2, 1.1) == topview::kTruth);  // the found vehicle's true footprint
  CHECK(at(5, 5) == topview::height_colour(2.0));
  CHECK(at(8, 9) == topview::height_colour(0));

  // Same inputs, same bytes; the default (density) pixel too.
  REQUIRE(test::sh(bin + args + " --size 200 -o " + (dir / "again.png").string(), dir / "err.txt", &err) == 0);
  CHECK(slurp(dir / "top.png") == slurp(dir / "again.png"));
  REQUIRE(test::sh(bin + args + " -o " + (dir / "auto1.png").string(), dir / "err.txt", &err) == 0);
  REQUIRE(test::sh(bin + args + " -o " + (dir / "auto2.png").string(), dir / "err.txt", &err) == 0);
  CHECK(slurp(dir / "auto1.png") == slurp(dir / "auto2.png"));
  CHECK(read_png(dir / "auto1.png").height == 1008);

  // Bad input: named, nothing written.
  std::ofstream((dir / "bad.json").string())
      << R"({"format":"canopy.detections","detections":[{"footprint":[[1,2]]}]})";
  CHECK(test::sh(bin + " -q -i " + (dir / "scan.pcd").string() + " --detections " +
                     (dir / "bad.json").string() + " -o " + (dir / "bad.png").string(),
                 dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("bad.json"));
  CHECK_FALSE(test::exists(dir / "bad.png"));
  // No --detections: a usage error that says what to give; --help says it is required.
  CHECK(test::sh(bin + " -q -i " + (dir / "scan.pcd").string() + " -o " + (dir / "nodet.png").string(),
                 dir / "err.txt", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--detections is required (collect's detections.json"));
  CHECK_FALSE(test::exists(dir / "nodet.png"));
  REQUIRE(test::sh(bin + " --help >" + (dir / "help.txt").string(), dir / "err.txt", &err) == 0);
  CHECK_THAT(slurp(dir / "help.txt"), Catch::Contains("required (a picture draws a tile's detections)"));
  // Beyond the bound, or both --size and --pixel: a usage error, nothing written.
  CHECK(test::sh(bin + args + " --size 8192 -o " + (dir / "big.png").string(), dir / "err.txt", &err) == 2);
  CHECK_THAT(err, Catch::Contains("beyond the bound"));
  CHECK(test::sh(bin + args + " --size 100 --pixel 0.1 -o " + (dir / "big.png").string(), dir / "err.txt",
                 &err) == 2);
  CHECK_FALSE(test::exists(dir / "big.png"));
}

namespace {

// The round-3 reproducers (../shared/data/malformed/round3/topview/), as text.
const char* kDetections =
    R"({"detections":[{"candidate":"c1","footprint":[[500001.0,5400001.0],[500003.0,5400001.0],)"
    R"([500003.0,5400002.0],[500001.0,5400002.0]]}],"format":"canopy.detections","version":1})";
const char* kTruth =
    R"({"format":"canopy.scene_truth","vehicles":[{"footprint":[[500001.1,5400001.1],[500002.9,5400001.1],)"
    R"([500002.9,5400001.9],[500001.1,5400001.9]],"instance":1},{"footprint":[[500007.0,5400007.0],)"
    R"([500009.0,5400007.0],[500009.0,5400008.0],[500007.0,5400008.0]],"instance":2}],"version":1})";
const char* kScore =
    R"({"format":"canopy.scene_score","matches":[{"candidate":"c1","instance":1,"outcome":"wrong","tile":0},)"
    R"({"candidate":null,"instance":2,"outcome":"missed","tile":0}],"tiles":[{}],"version":1})";

// Writes the three documents, `which` ("d", "t" or "s") replaced by `text`; returns the
// footprints read, or throws.
std::vector<topview::Shape> read_with(const fs::path& dir, const std::string& which, const std::string& text) {
  std::ofstream((dir / "d.json").string()) << (which == "d" ? text : kDetections);
  std::ofstream((dir / "t.json").string()) << (which == "t" ? text : kTruth);
  std::ofstream((dir / "s.json").string()) << (which == "s" ? text : kScore);
  return topview::read_footprints(
             {(dir / "d.json").string(), (dir / "t.json").string(), (dir / "s.json").string(), ""}, 0)
      .shapes;
}

// The document with `from` replaced by `to` (once; the test fails if `from` is absent).
std::string edit(const char* doc, const std::string& from, const std::string& to) {
  std::string s = doc;
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("topview reads every member it uses, naming the file and the member (round 3, cases 4, 5)") {
  const fs::path dir = test::fresh_dir("topview", "members");
  // The reproducers' valid set: truth (white, the missed one yellow), then the wrong detection.
  const auto shapes = read_with(dir, "", "");
  REQUIRE(shapes.size() == 3);
  CHECK(shapes[0].kind == topview::Kind::truth);
  CHECK(shapes[1].kind == topview::Kind::missed);
  CHECK(shapes[2].kind == topview::Kind::wrong);
  CHECK(shapes[2].ring[1][0] == 500003.0);

  const std::string d = (dir / "d.json").string(), t = (dir / "t.json").string(), s = (dir / "s.json").string();
  struct Bad {
    std::string which, text, file, message;
  };
  const std::vector<Bad> bad{
      // case 4: a match without "outcome" (read past a heap block before), or without "candidate"
      {"s", edit(kScore, R"("outcome":"wrong",)", ""), s, "matches[0]: missing \"outcome\""},
      {"s", edit(kScore, R"("candidate":"c1",)", ""), s, "matches[0]: missing \"candidate\""},
      {"s", edit(kScore, R"("instance":2,)", ""), s, "matches[1]: missing \"instance\""},
      {"s", edit(kScore, R"("outcome":"wrong")", R"("outcome":"bad")"), s,
       "matches[0].outcome must be right, wrong, false_alarm or missed, not \"bad\""},
      {"s", edit(kScore, R"("outcome":"wrong")", R"("outcome":3)"), s,
       "matches[0].outcome must be a string, not 3"},
      {"s", edit(kScore, R"("tile":0})", R"("tile":0.0})"), s,
       "matches[0].tile must be a non-negative integer, not 0.0"},
      {"s", edit(kScore, R"("tile":0})", R"("tile":5})"), s, "matches[0].tile 5 is not one of the 1 tiles"},
      {"s", edit(kScore, R"("matches":[)", R"("matches":[7,)"), s, "matches[0] must be an object, not 7"},
      {"s", edit(kScore, R"("matches":[)", R"("other":[)"), s, "score: missing \"matches\""},
      {"s", edit(kScore, R"("tiles":[{}])", R"("tiles":[])"), s,
       "matches[0].tile 0 is not one of the 0 tiles"},
      {"s", R"({"format":"canopy.scene_score","version":1,"tiles":[],"matches":[]})", s,
       "has no tile 0 (0 tiles)"},
      {"s", edit(kScore, R"("outcome":"missed")", R"("outcome":"wrong")"), s,
       "matches[1]: missing \"candidate\""},
      {"s", edit(kScore, R"("tiles":[{}])", R"("tiles":{})"), s,
       "score.tiles must be an array, not an object"},
      {"s", edit(kScore, R"("version":1)", R"("version":2)"), s, "version 2"},
      // case 5: a null candidate, version 2, missing arrays, wrong types
      {"d", edit(kDetections, R"("candidate":"c1")", R"("candidate":null)"), d,
       "detections[0].candidate must be a string, not null"},
      {"d", edit(kDetections, R"("version":1)", R"("version":3)"), d, "version 3"},
      {"d", edit(kDetections, R"("version":1)", R"("version":1.5)"), d, "version"},
      {"d", edit(kDetections, R"(,"version":1)", ""), d, "version"},
      {"d", edit(kDetections, R"("detections":[)", R"("found":[)"), d,
       "detections document: missing \"detections\""},
      {"d", edit(kDetections, R"("detections":[{)", R"("detections":[3,{)"), d,
       "detections[0] must be an object"},
      {"d", edit(kDetections, R"([500001.0,5400001.0],)", R"([500001.0,"x"],)"), d,
       "detections[0].footprint[0] must be [x, y], not an array"},
      {"d", edit(kDetections, R"("footprint":[)", R"("footprint":[[0,0],)"), d, ""},  // 5 corners: fine
      {"t", edit(kTruth, R"("instance":1)", R"("instance":-1)"), t,
       "vehicles[0].instance must be a non-negative integer, not -1"},
      {"t", edit(kTruth, R"("instance":1)", R"("instance":"1")"), t,
       "vehicles[0].instance must be a non-negative integer"},
      {"t", edit(kTruth, R"("vehicles":[)", R"("cars":[)"), t, "truth: missing \"vehicles\""},
      {"t", edit(kTruth, R"("format":"canopy.scene_truth")", R"("format":"canopy.detections")"), t,
       "canopy.scene_truth"},
      {"t", "{\"format\":\"canopy.scene_truth\",\"version\":1,\"vehicles\":[{\"instance\":1}]}", t,
       "vehicles[0]: missing \"footprint\""},
  };
  for (const auto& b : bad) {
    INFO(b.text);
    if (b.message.empty()) {
      CHECK_NOTHROW(read_with(dir, b.which, b.text));
      continue;
    }
    try {
      read_with(dir, b.which, b.text);
      FAIL("accepted");
    } catch (const common::DataError& e) {
      CHECK(e.file() == b.file);
      CHECK_THAT(e.what(), Catch::Contains(b.message));
      CHECK_THAT(e.what(), !Catch::Contains("json.exception"));
    }
  }

  // The CLI: exit 1, the file named, no picture.
  formats::write_pcd(scan(), (dir / "scan.pcd").string());
  std::ofstream(s) << edit(kScore, R"("outcome":"wrong",)", "");
  std::string err;
  CHECK(test::sh(std::string(CANOPY_BIN_DIR) + "/topview -q -i " + (dir / "scan.pcd").string() +
                     " --detections " + d + " --truth " + t + " --score " + s + " --size 64 -o " +
                     (dir / "top.png").string(),
                 dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains(s + ": matches[0]: missing \"outcome\""));
  CHECK_FALSE(test::exists(dir / "top.png"));
}

TEST_CASE("topview finds its tile in the score by the detections path, not by make's order (issue 30)") {
  const fs::path dir = test::fresh_dir("topview", "tile_lookup");
  const std::string d = (dir / "d.json").string(), t = (dir / "t.json").string(), s = (dir / "s.json").string();
  std::ofstream(d) << kDetections;
  std::ofstream(t) << kTruth;
  // Two tiles: ours is the second; the first tile's match says "right", ours "wrong".
  auto score = [&](const std::string& first, const std::string& second) {
    std::ofstream(s) << R"({"format":"canopy.scene_score","version":1,"tiles":[{"detections":")" + first +
                            R"("},{"detections":")" + second +
                            R"("}],"matches":[{"candidate":"c1","instance":1,"outcome":"right","tile":0},)"
                            R"({"candidate":"c1","instance":1,"outcome":"wrong","tile":1}]})";
  };
  auto kind_of_detection = [&](int tile) {
    const auto shapes = topview::read_footprints({d, t, s, ""}, tile).shapes;
    REQUIRE(!shapes.empty());
    return shapes.back().kind;
  };
  score("other/d.json", d);
  CHECK(kind_of_detection(-1) == topview::Kind::wrong);  // looked up: tile 1
  CHECK(kind_of_detection(0) == topview::Kind::right);   // --tile 0 given
  score(d, "other/d.json");
  CHECK(kind_of_detection(-1) == topview::Kind::right);
  score("a/d.json", "b/d.json");
  CHECK_THROWS_WITH(kind_of_detection(-1), Catch::Contains("has no tile whose detections is " + d) &&
                                               Catch::Contains("give --tile"));
  score(d, d);
  CHECK_THROWS_WITH(kind_of_detection(-1), Catch::Contains("lists the detections " + d + " twice"));
  // A score of one tile: that tile, whatever its path (a score made by hand elsewhere).
  std::ofstream(s) << kScore;
  CHECK(kind_of_detection(-1) == topview::Kind::wrong);
  topview::Params p;
  p.tile = -2;
  CHECK_THROWS_AS(topview::validate(p), common::UsageError);
}

TEST_CASE("a height raster draws the same picture as the points, the tile read once (issue 31)") {
  const formats::PointCloud pc = scan(1.5, 0, 312.4);
  const formats::HeightRaster r = topview::raster(pc, {});
  // The grid render() picks without footprints: 0.07 m data pixels from the points' corner,
  // the highest height above ground per pixel before the gaps are filled.
  CHECK(r.width == 144);
  CHECK(r.height == 144);
  CHECK(r.pixel == 0.07);
  CHECK(r.x0 == E + 0.025);
  CHECK(r.y1 == N + 9.975);
  CHECK(r.box_x0 == E + 0.025);
  CHECK(r.box_y1 == N + 9.975);
  CHECK(r.density == Approx(400));
  auto value = [&r](double x, double y) {
    return r.at(static_cast<int>((E + x - r.x0) / r.pixel), static_cast<int>((r.y1 - (N + y)) / r.pixel));
  };
  CHECK(value(5, 5) == Approx(1.5).margin(0.1));
  CHECK(value(8, 8) == Approx(0).margin(0.1));
  const auto empty = std::count_if(r.values.begin(), r.values.end(), [](float v) { return std::isnan(v); });
  CHECK(empty > 0);  // 0.07 m pixels over 0.05 m spacing: some hold no point (filled when drawn)

  // Footprints inside the points' box: the same picture, pixel for pixel.
  const topview::Footprints fp =
      shapes({{rect(4, 4, 6, 6), topview::Kind::model}, {rect(1, 1, 3, 2), topview::Kind::rejected}});
  const topview::Image direct = topview::render(pc, fp, {});
  const topview::Image drawn = topview::render(r, fp, {});
  CHECK(drawn.width == direct.width);
  CHECK(drawn.height == direct.height);
  CHECK(drawn.zoom == direct.zoom);
  CHECK(drawn.rgb == direct.rgb);
  CHECK(at(drawn, 5, 5) == topview::height_colour(1.5));
  CHECK(near(drawn, 4, 5, topview::kModel));
  CHECK(near(drawn, 2, 1, topview::kRejected));
  CHECK(topview::encode_png(drawn) == topview::encode_png(direct));

  // Footprints beyond the points (east, north and west) widen the map by whole data pixels
  // from the points' corner, from the raster as from the points: the same picture again.
  const topview::Footprints out = shapes({{rect(9, 4, 11.03, 6), topview::Kind::cls},
                                          {rect(3, 9, 4, 10.5), topview::Kind::failed},
                                          {rect(-0.6, 3, 1, 4), topview::Kind::none}});
  const topview::Image wide = topview::render(r, out, {});
  const topview::Image wide_direct = topview::render(pc, out, {});
  CHECK(wide.map_width == wide_direct.map_width);
  CHECK(wide.map_height == wide_direct.map_height);
  CHECK(wide.grid_col == 9);  // ceil((0.025 + 0.6) / 0.07): the points' corner 9 data pixels in
  CHECK(wide.grid_row == 8);  // ceil((10.5 - 9.975) / 0.07)
  CHECK(wide.x0 == Approx(E + 0.025 - 9 * 0.07));
  CHECK(wide.rgb == wide_direct.rgb);
  CHECK(at(wide, 5, 5) == topview::height_colour(1.5));
  CHECK(distance(at(wide, 8, 8), topview::height_colour(0)) <= 30);
  CHECK(near(wide, 11.03, 5, topview::kClass));
  CHECK(near(wide, 3.5, 10.5, topview::kFailed));

  // The raster's pixel is the raster's: --pixel / --size refused.
  topview::Params p;
  p.pixel = 0.1;
  CHECK_THROWS_AS(topview::render(r, fp, p), common::UsageError);
}

TEST_CASE("topview CLI: --raster-out then --raster gives the bytes -i gives; bad uses refused") {
  const fs::path dir = test::fresh_dir("topview", "raster");
  formats::write_pcd(scan(), (dir / "scan.pcd").string());
  const Json det{{"format", "canopy.detections"},
                 {"version", 1},
                 {"detections", {{{"candidate", "c1"}, {"footprint", footprint(rect(1, 1, 3, 2))}}}}};
  write_json(dir / "d.json", det);
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/topview -q";
  const std::string d = " --detections " + (dir / "d.json").string();
  std::string err;
  REQUIRE(test::sh(bin + " -i " + (dir / "scan.pcd").string() + " --raster-out " + (dir / "top.raster").string(),
                   dir / "err.txt", &err) == 0);
  CHECK(formats::read_height_raster((dir / "top.raster").string()).width == 144);
  REQUIRE(test::sh(bin + " --raster " + (dir / "top.raster").string() + d + " -o " + (dir / "r.png").string(),
                   dir / "err.txt", &err) == 0);
  REQUIRE(test::sh(bin + " -i " + (dir / "scan.pcd").string() + d + " -o " + (dir / "i.png").string(),
                   dir / "err.txt", &err) == 0);
  CHECK(slurp(dir / "r.png") == slurp(dir / "i.png"));
  // --png default: libpng's defaults, the same pixels.
  REQUIRE(test::sh(bin + " -i " + (dir / "scan.pcd").string() + d + " --png default -o " +
                       (dir / "slow.png").string(),
                   dir / "err.txt", &err) == 0);
  CHECK(read_png(dir / "slow.png").rgb == read_png(dir / "i.png").rgb);

  // A raster that is not one: exit 1, the file named.
  std::ofstream((dir / "bad.raster").string()) << "canopy.height_raster 1\nwidth 2\n";
  CHECK(test::sh(bin + " --raster " + (dir / "bad.raster").string() + d + " -o " + (dir / "b.png").string(),
                 dir / "err.txt", &err) == 1);
  CHECK(err.find("bad.raster") != std::string::npos);
  CHECK(!fs::exists(dir / "b.png"));
  // Usage: both -i and --raster; --raster-out with --detections; --pixel with --raster; --png.
  CHECK(test::sh(bin + " -i " + (dir / "scan.pcd").string() + " --raster " + (dir / "top.raster").string() +
                     d + " -o " + (dir / "b.png").string(),
                 dir / "err.txt", &err) == 2);
  CHECK(test::sh(bin + " -i " + (dir / "scan.pcd").string() + d + " --raster-out " + (dir / "x.raster").string(),
                 dir / "err.txt", &err) == 2);
  CHECK(test::sh(bin + " --raster " + (dir / "top.raster").string() + d + " --pixel 0.1 -o " +
                     (dir / "b.png").string(),
                 dir / "err.txt", &err) == 2);
  CHECK(test::sh(bin + " -i " + (dir / "scan.pcd").string() + d + " --png best -o " + (dir / "b.png").string(),
                 dir / "err.txt", &err) == 2);
  CHECK(!fs::exists(dir / "b.png"));
}

TEST_CASE("check_tile: a document none of whose footprints comes within 10 m of the points is refused") {
  const std::array<double, 4> box{E, N, E + 10, N + 10};
  auto fp = [](std::vector<topview::Shape> s) {
    topview::Footprints f = shapes(std::move(s));
    f.detections_file = "b/detections.json";
    f.truth_file = "a/truth.json";
    f.detections_tile = "b.laz";
    return f;
  };
  // 9.9 m beyond the east edge: within the margin; 10.1 m: beyond.
  CHECK_NOTHROW(topview::check_tile(fp({{rect(19.9, 1, 22, 2), topview::Kind::cls}}), "a.laz", box));
  CHECK_THROWS_WITH(
      topview::check_tile(fp({{rect(20.1, 1, 22, 2), topview::Kind::cls}}), "a.laz", box),
      "b/detections.json: none of its 1 footprints (detections and rejected candidates) lies within 10 m of "
      "the "
      "points of a.laz (x 500000.0 to 500010.0, y 5400000.0 to 5400010.0; the footprints: x 500020.1 to "
      "500022.0, "
      "y 5400001.0 to 5400002.0): the detections of another tile? (they record the tile b.laz)");
  // Below, left, above: beyond too; rejected candidates count with the detections.
  CHECK_THROWS_AS(topview::check_tile(fp({{rect(1, -20, 2, -10.5), topview::Kind::rejected}}), "a.laz", box),
                  common::DataError);
  CHECK_THROWS_AS(topview::check_tile(fp({{rect(-30, 1, -10.2, 2), topview::Kind::model}}), "a.laz", box),
                  common::DataError);
  CHECK_THROWS_AS(topview::check_tile(fp({{rect(1, 20.5, 2, 22), topview::Kind::none}}), "a.laz", box),
                  common::DataError);
  // A footprint larger than the tile, over it: within.
  CHECK_NOTHROW(topview::check_tile(fp({{rect(-50, -50, 60, 60), topview::Kind::rejected}}), "a.laz", box));
  // One within, one far: drawn (a warning), not refused.
  CHECK_NOTHROW(topview::check_tile(
      fp({{rect(1, 1, 2, 2), topview::Kind::model}, {rect(3000, 1, 3002, 2), topview::Kind::model}}), "a.laz",
      box));
  // The truth is judged apart: true vehicles of another tile name the truth file.
  CHECK_THROWS_WITH(
      topview::check_tile(fp({{rect(1, 1, 2, 2), topview::Kind::model},
                              {rect(5000, 5000, 5002, 5001), topview::Kind::truth},
                              {rect(5010, 5000, 5012, 5001), topview::Kind::missed}}),
                          "a.laz", box),
      Catch::StartsWith("a/truth.json: none of its 2 true vehicles' footprints lies within 10 m") &&
          Catch::EndsWith("the truth of another tile?"));
  // No footprint at all: nothing to judge.
  CHECK_NOTHROW(topview::check_tile(fp({}), "a.laz", box));
}

TEST_CASE("topview CLI: detections of another tile are refused naming both files, from -i and --raster") {
  const fs::path dir = test::fresh_dir("topview", "other_tile");
  formats::write_pcd(scan(), (dir / "scan.pcd").string());
  // Tile B, 2 km east: its detection and its rejected candidate (from B's index).
  const Json index{{"format", "canopy.candidates"},
                   {"version", 1},
                   {"candidates",
                    {{{"id", "c2"},
                      {"transform", {{1, 0, 0, E + 2005}, {0, 1, 0, N + 5}, {0, 0, 1, 0}, {0, 0, 0, 1}}},
                      {"centre", {E + 2005, N + 5, 0}},
                      {"length", 4},
                      {"width", 2},
                      {"heading", 0}}}}};
  write_json(dir / "b_index.json", index);
  const Json far{{"format", "canopy.detections"},
                 {"version", 2},
                 {"tile", "b.laz"},
                 {"index", (dir / "b_index.json").string()},
                 {"detections",
                  {{{"candidate", "c1"},
                    {"level", "class"},
                    {"class", "sedan"},
                    {"group", "car"},
                    {"footprint", footprint(rect(2001, 1, 2003, 2))}}}},
                 {"rejected", {{{"candidate", "c2"}, {"reason", "too_small"}}}}};
  write_json(dir / "b_detections.json", far);
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/topview -q";
  const std::string d = " --detections " + (dir / "b_detections.json").string();
  std::string err;
  // Before stop 70: exit 0 and a 2000 m wide picture at 1.6 m pixels (-i), or a refusal blaming
  // the raster's pixel size (--raster).
  CHECK(test::sh(bin + " -i " + (dir / "scan.pcd").string() + d + " -o " + (dir / "m.png").string(),
                 dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("b_detections.json: none of its 2 footprints (detections and rejected "
                                  "candidates) lies within 10 m of the points of " +
                                  (dir / "scan.pcd").string()));
  CHECK_THAT(err, Catch::Contains("the detections of another tile? (they record the tile b.laz)"));
  CHECK_FALSE(fs::exists(dir / "m.png"));
  REQUIRE(test::sh(bin + " -i " + (dir / "scan.pcd").string() + " --raster-out " + (dir / "a.raster").string(),
                   dir / "err.txt", &err) == 0);
  CHECK(test::sh(bin + " --raster " + (dir / "a.raster").string() + d + " -o " + (dir / "m.png").string(),
                 dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("b_detections.json: none of its 2 footprints") &&
                      Catch::Contains("of the points of " + (dir / "a.raster").string()) &&
                      Catch::Contains("the detections of another tile?"));
  CHECK_FALSE(fs::exists(dir / "m.png"));
  // Its own detections beside the far one: drawn, with a warning.
  Json mixed = far;
  mixed["detections"].push_back({{"candidate", "c3"},
                                 {"level", "class"},
                                 {"class", "sedan"},
                                 {"group", "car"},
                                 {"footprint", footprint(rect(1, 1, 3, 2))}});
  write_json(dir / "mixed.json", mixed);
  CHECK(test::sh(bin + " -i " + (dir / "scan.pcd").string() + " --detections " +
                     (dir / "mixed.json").string() + " -o " + (dir / "mixed.png").string(),
                 dir / "err.txt", &err) == 0);
  CHECK_THAT(err, Catch::Contains("warning: " + (dir / "mixed.json").string() + ": 2 of its 3 footprints"));
  CHECK(fs::exists(dir / "mixed.png"));
  // A footprint 5 m beyond the points (a candidate at the tile's edge): no word.
  Json edge = far;
  edge.erase("rejected");
  edge["detections"][0]["footprint"] = footprint(rect(12, 1, 15, 2));
  write_json(dir / "edge.json", edge);
  CHECK(test::sh(bin + " -i " + (dir / "scan.pcd").string() + " --detections " +
                     (dir / "edge.json").string() + " -o " + (dir / "edge.png").string(),
                 dir / "err.txt", &err) == 0);
  CHECK(err.empty());
}
