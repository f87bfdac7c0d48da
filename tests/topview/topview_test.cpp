// topview: a hand-placed scan and footprints; pixel colours checked where the outlines must be.
#include <png.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/formats/pcd.h"
#include "support/cli.h"
#include "topview/topview.h"

using namespace canopy;
using Json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

// 10 x 10 m of ground at z = 0 (0.05 m grid) with a 2 x 2 m block at z = 2 over [4, 6]^2,
// shifted to UTM coordinates.
const double E = 500000, N = 5400000;
formats::PointCloud scan() {
  formats::PointCloud pc;
  auto& x = pc.add("x", formats::kFloat64);
  auto& y = pc.add("y", formats::kFloat64);
  auto& z = pc.add("z", formats::kFloat64);
  for (int i = 0; i <= 200; ++i) {
    for (int j = 0; j <= 200; ++j) {
      const double px = i * 0.05, py = j * 0.05;
      x.push_back(E + px);
      y.push_back(N + py);
      z.push_back(px >= 4 && px <= 6 && py >= 4 && py <= 6 ? 2.0 : 0.0);
    }
  }
  pc.resize(x.size());
  return pc;
}

topview::Ring rect(double ax, double ay, double bx, double by) {
  return {{E + ax, N + ay}, {E + bx, N + ay}, {E + bx, N + by}, {E + ax, N + by}};
}

// Pixel (col, row) of tile point (x, y).
std::pair<int, int> px(const topview::Image& img, double x, double y) {
  return {static_cast<int>((E + x - img.x0) / img.pixel), static_cast<int>((img.y1 - (N + y)) / img.pixel)};
}

}  // namespace

TEST_CASE("render: grey by height, outlines on the footprint edges only") {
  const topview::Image img = topview::render(scan(), {{rect(1, 1, 3, 2), topview::kRight}}, 100);
  CHECK(img.pixel == Approx(0.1));
  CHECK(img.width == 101);
  CHECK(img.height == 101);
  const auto [bc, br] = px(img, 5, 5);
  const auto [gc, gr] = px(img, 8, 8);
  CHECK(img.at(bc, br)[0] > img.at(gc, gr)[0]);   // the block is brighter than the ground
  CHECK(img.at(bc, br)[0] == img.at(bc, br)[1]);  // grey
  const auto [ec, er] = px(img, 2, 1);
  CHECK(img.at(ec, er) == topview::kRight);  // on the bottom edge
  const auto [ic, ir] = px(img, 2, 1.5);
  CHECK(img.at(ic, ir) != topview::kRight);  // inside: not filled
  // North is up: the block's top edge (y = 6) is above its bottom edge (y = 4).
  CHECK(px(img, 5, 6).second < px(img, 5, 4).second);
}

TEST_CASE("topview CLI: outcome colours from a score, missed vehicles in yellow") {
  const fs::path dir = test::fresh_dir("topview", "cli");
  formats::write_pcd(scan(), (dir / "scan.pcd").string());
  auto fp = [](const topview::Ring& r) {
    Json a = Json::array();
    for (const auto& p : r) a.push_back({p[0], p[1]});
    return a;
  };
  const Json det{{"format", "canopy.detections"},
                 {"version", 1},
                 {"detections", {{{"candidate", "c1"}, {"footprint", fp(rect(1, 1, 3, 2))}}}}};
  const Json truth{{"format", "canopy.scene_truth"},
                   {"version", 1},
                   {"vehicles",
                    {{{"instance", 1}, {"footprint", fp(rect(1.1, 1.1, 2.9, 1.9))}},
                     {{"instance", 2}, {"footprint", fp(rect(7, 7, 9, 8))}}}}};
  const Json score{{"format", "canopy.scene_score"},
                   {"version", 1},
                   {"tiles", {Json::object()}},
                   {"matches",
                    {{{"tile", 0}, {"candidate", "c1"}, {"outcome", "wrong"}, {"instance", 1}},
                     {{"tile", 0}, {"candidate", nullptr}, {"outcome", "missed"}, {"instance", 2}}}}};
  std::ofstream((dir / "d.json").string()) << det.dump();
  std::ofstream((dir / "t.json").string()) << truth.dump();
  std::ofstream((dir / "s.json").string()) << score.dump();
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/topview";
  std::string err;
  REQUIRE(test::sh(bin + " -q -i " + (dir / "scan.pcd").string() + " --detections " +
                       (dir / "d.json").string() + " --truth " + (dir / "t.json").string() + " --score " +
                       (dir / "s.json").string() + " --size 200 -o " + (dir / "top.png").string(),
                   dir / "err.txt", &err) == 0);
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  REQUIRE(png_image_begin_read_from_file(&png, (dir / "top.png").string().c_str()) != 0);
  png.format = PNG_FORMAT_RGB;
  std::vector<std::uint8_t> rgb(PNG_IMAGE_SIZE(png));
  REQUIRE(png_image_finish_read(&png, nullptr, rgb.data(), 0, nullptr) != 0);
  CHECK(png.width == 201);
  CHECK(png.height == 201);
  auto at = [&](double x, double y) {  // 0.05 m pixels from (0, 10) at the top left
    const int c = static_cast<int>(x / 0.05), r = static_cast<int>((10 - y) / 0.05);
    const std::size_t i = 3 * (static_cast<std::size_t>(r) * png.width + c);
    return topview::Rgb{rgb[i], rgb[i + 1], rgb[i + 2]};
  };
  CHECK(at(2, 1) == topview::kWrong);    // the detection, wrong model
  CHECK(at(8, 7) == topview::kMissed);   // the missed vehicle
  CHECK(at(2, 1.1) == topview::kTruth);  // the found vehicle's true footprint
  CHECK(at(5, 5)[0] > at(8, 9)[0]);      // block above ground

  // Bad input: named, nothing written.
  std::ofstream((dir / "bad.json").string())
      << R"({"format":"canopy.detections","detections":[{"footprint":[[1,2]]}]})";
  CHECK(test::sh(bin + " -q -i " + (dir / "scan.pcd").string() + " --detections " +
                     (dir / "bad.json").string() + " -o " + (dir / "bad.png").string(),
                 dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("bad.json"));
  CHECK_FALSE(test::exists(dir / "bad.png"));
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
      {(dir / "d.json").string(), (dir / "t.json").string(), (dir / "s.json").string()}, 0);
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
  CHECK(shapes[0].colour == topview::kTruth);
  CHECK(shapes[1].colour == topview::kMissed);
  CHECK(shapes[2].colour == topview::kWrong);
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
      {"s", edit(kScore, R"("tiles":[{}])", R"("tiles":[])"), s, "has no tile 0 (0 tiles)"},
      {"s", edit(kScore, R"("tiles":[{}])", R"("tiles":{})"), s,
       "score.tiles must be an array, not an object"},
      {"s", edit(kScore, R"("version":1)", R"("version":2)"), s, "version 2"},
      // case 5: a null candidate, version 2, missing arrays, wrong types
      {"d", edit(kDetections, R"("candidate":"c1")", R"("candidate":null)"), d,
       "detections[0].candidate must be a string, not null"},
      {"d", edit(kDetections, R"("version":1)", R"("version":2)"), d, "version 2"},
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
