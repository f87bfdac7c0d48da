// The detect binary: output directory, index.json, bad input, and the existing chain on a
// candidate.
#include <sys/stat.h>

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "canopy/common/math.h"
#include "canopy/formats/labels.h"
#include "canopy/formats/las.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/points_io.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/trajectory.h"
#include "support/cli.h"
#include "fixtures/detect_synth_tile.h"
#include "las/las_bytes.h"

using namespace canopy;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

const std::string kBin = CANOPY_BIN_DIR;

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

Json read_json(const fs::path& p) {
  std::ifstream f(p);
  return Json::parse(f);
}

// Nothing but `keep` in dir (no temporary directories left behind).
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

detect_test::TileSpec small_scene() {
  detect_test::TileSpec s;
  s.half_extent = 15;
  s.seed = 21;
  s.offset = Eigen::Vector3d(500000, 4400000, 200);
  s.terrain = detect_test::Terrain::kSlope;
  s.slope_deg = 8;
  s.vehicles = {{-5, 3, 0.7, 4.5, 1.8, 1.5, 4}, {6, -4, -0.3, 7.0, 2.4, 2.8, 6}};
  s.trees = {{0, -9, 3, 5, 10, 0.2}};
  s.boulders = {{8, 8, 0.6}};
  return s;
}

// The replay's box tile (../shared/data/malformed/round3/gen-box-tile.py): 40 x 40 m of flat
// ground (0.25 m grid) and one 4.6 x 1.9 x 1.5 m box; detect finds one candidate.
formats::PointCloud box_tile() {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 160; ++i)
    for (int j = 0; j < 160; ++j) p.emplace_back(i * 0.25, j * 0.25, 0.0);
  for (int i = 0; i < 46; ++i)
    for (int j = 0; j < 19; ++j) p.emplace_back(10 + i * 0.1, 10 + j * 0.1, 1.5);
  for (int i = 0; i < 46; ++i)
    for (int k = 0; k < 15; ++k) {
      p.emplace_back(10 + i * 0.1, 10, k * 0.1);
      p.emplace_back(10 + i * 0.1, 11.8, k * 0.1);
    }
  formats::PointCloud c;
  auto& x = c.add("x", formats::kFloat64);
  auto& y = c.add("y", formats::kFloat64);
  auto& z = c.add("z", formats::kFloat64);
  c.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    x[i] = p[i].x();
    y[i] = p[i].y();
    z[i] = p[i].z();
  }
  return c;
}

}  // namespace

TEST_CASE("detect writes a candidates directory") {
  const fs::path dir = test::fresh_dir("detect", "cli_ok");
  const auto s = small_scene();
  formats::write_pcd(detect_test::make_tile(s), (dir / "tile.pcd").string());
  std::string err;
  const fs::path out = dir / "cands";
  REQUIRE(test::sh(kBin + "/detect -i " + q(dir / "tile.pcd") + " -o " + q(out) + "/", dir / "err.txt",
                   &err) == 0);
  INFO(err);
  const Json j = read_json(out / "index.json");
  CHECK(j["format"] == "canopy.candidates");
  CHECK(j["version"] == 2);
  CHECK(j["margin"] == 0.5);
  // No ground truth in the index (issue 30): candtruth writes it from the labelled tile.
  CHECK(!j.contains("instances"));
  CHECK(j["provenance"]["tool"] == "detect");
  CHECK(j["tile_points"].get<std::size_t>() > 10000);
  REQUIRE(j["candidates"].size() == 2);
  for (const auto& c : j["candidates"]) {
    const formats::PointCloud cloud = formats::read_pcd((out / c["file"].get<std::string>()).string());
    CHECK(cloud.size() == c["point_count"].get<std::size_t>());
    CHECK(!cloud.has("instance"));
    CHECK(!cloud.has("label"));
    CHECK(cloud.has("sensor_x"));
    // The transform's translation is the centre, at UTM magnitudes, exact in float64.
    CHECK(c["transform"][0][3].get<double>() == c["centre"][0].get<double>());
    CHECK(std::abs(c["centre"][0].get<double>() - 500000) < 15);
    CHECK(std::abs(c["centre"][1].get<double>() - 4400000) < 15);
    CHECK(!c.contains("truth"));
    // Comments: the tile's, detect's provenance (formats::provenance_comments), the candidate.
    const auto& com = cloud.comments;
    const auto prov = std::find_if(com.begin(), com.end(),
                                   [](const std::string& l) { return l.rfind("detect (canopy) ", 0) == 0; });
    REQUIRE(prov != com.end());
    CHECK(std::find(prov, com.end(), "parameter cell = 500mm") != com.end());
    CHECK(std::find(prov, com.end(), "parameter clustering = grid") != com.end());
    CHECK(std::find(prov, com.end(), "input " + (dir / "tile.pcd").string()) != com.end());
    CHECK(com.back() == "candidate " + c["id"].get<std::string>() +
                            " in its local frame; index.json gives the transform back to the tile");
  }
  {
    // candtruth: each of the two vehicles is one candidate's, covered; its crop is the crop's.
    const fs::path tdir = test::fresh_dir("detect", "cli_ok_truth");
    REQUIRE(test::sh(kBin + "/candtruth -i " + q(out / "index.json") + " --tile " + q(dir / "tile.pcd") +
                         " -o " + q(tdir / "truth.json"),
                     tdir / "err.txt", &err) == 0);
    CHECK(err.find("2 of 2 labelled vehicles covered") != std::string::npos);
    const Json t = read_json(tdir / "truth.json");
    CHECK(t["format"] == "canopy.candidate_truth");
    REQUIRE(t["instances"].size() == 2);
    for (const auto& it : t["instances"]) CHECK(it["candidates"].size() == 1);
    REQUIRE(t["candidates"].size() == 2);
    for (std::size_t k = 0; k < 2; ++k) {
      CHECK(t["candidates"][k]["id"] == j["candidates"][k]["id"]);
      CHECK(t["candidates"][k]["crop_points"] == j["candidates"][k]["point_count"]);
      CHECK(t["candidates"][k]["coverage"].get<double>() > 0.95);
    }
  }
  const formats::Mesh classes = formats::read_ply((out / "classes.ply").string());
  CHECK(classes.vertices.size() == j["tile_points"].get<std::size_t>());
  CHECK(classes.vertices.has("class"));
  CHECK(classes.vertices.has("red"));
  const std::vector<std::string>& cc = classes.vertices.comments;
  REQUIRE(cc.size() >= 3);
  CHECK(cc.front().rfind("detect (canopy) ", 0) == 0);
  CHECK(std::find(cc.begin(), cc.end(), "input " + (dir / "tile.pcd").string()) != cc.end());
  CHECK(cc[cc.size() - 2] == "classes 1 ground (brown), 2 vegetation/other (green), 3 candidate (red)");
  CHECK(cc.back().rfind("origin ", 0) == 0);
  CHECK(entries(dir) == std::vector<std::string>{"cands", "err.txt", "tile.pcd"});

  SECTION("a re-run replaces the previous output as a whole, and only that") {
    REQUIRE(test::sh(kBin + "/detect -q --no-classes -i " + q(dir / "tile.pcd") + " -o " + q(out),
                     dir / "err.txt", &err) == 0);
    CHECK(!fs::exists(out / "classes.ply"));
    CHECK(read_json(out / "index.json")["classes"].is_null());
    CHECK(entries(dir) == std::vector<std::string>{"cands", "err.txt", "tile.pcd"});
    CHECK(entries(out) == std::vector<std::string>{"c0001.pcd", "c0002.pcd", "index.json", "manifest.json"});
    // A file the user added is not detect's to delete (issue 25): refused, nothing changed.
    { std::ofstream(out / "stale.txt") << "old"; }
    CHECK(test::sh(kBin + "/detect -q -i " + q(dir / "tile.pcd") + " -o " + q(out), dir / "err.txt", &err) == 1);
    CHECK(err.find(out.string() + ": refusing to replace it") != std::string::npos);
    CHECK(err.find("stale.txt, which detect did not write") != std::string::npos);
    CHECK(entries(out) ==
          std::vector<std::string>{"c0001.pcd", "c0002.pcd", "index.json", "manifest.json", "stale.txt"});
    CHECK(read_json(out / "index.json")["classes"].is_null());  // still the previous output
  }
  SECTION("re-runs into the make layout: the chain's per-candidate directories inside, twice, via stagerun") {
    // mk/scenes.mk runs `stagerun DIR/detect -- detect -i SCAN -o DIR/cands` again when the
    // tile changed, into a cands/ holding cands/<id>/{samples.pcd, ...} (once: "cands: is a
    // directory, not an output file", when -o was checked as an output file).
    fs::create_directories(out / "c0001");
    { std::ofstream(out / "c0001" / "samples.pcd") << "old chain output"; }
    const std::string stage = std::string(kBin) + "/stagerun " + q(dir / "detect") + " -- ";
    for (const std::string& o : {out.string(), out.string() + "/"}) {
      INFO("-o " << o);
      REQUIRE(test::sh(stage + kBin + "/detect --no-classes -i " + q(dir / "tile.pcd") + " -o " + q(o),
                       dir / "err.txt", &err) == 0);
      CHECK(read_json(out / "index.json")["candidates"].size() == 2);
      CHECK(!fs::exists(out / "c0001"));  // the old chain outputs went with the old index
      CHECK(entries(dir) ==
            std::vector<std::string>{"cands", "detect.log", "detect.time", "err.txt", "tile.pcd"});
    }
  }
}

TEST_CASE("detect: bad output") {
  const fs::path dir = test::fresh_dir("detect", "cli_bad_output");
  formats::write_pcd(detect_test::make_tile(small_scene()), (dir / "tile.pcd").string());
  std::string err;
  SECTION("output is an existing file") {
    { std::ofstream(dir / "file.txt") << "keep me"; }
    CHECK(test::sh(kBin + "/detect -q -i " + q(dir / "tile.pcd") + " -o " + q(dir / "file.txt"),
                   dir / "err.txt", &err) == 1);
    CHECK(err.find("not a directory") != std::string::npos);
    std::ifstream f(dir / "file.txt");
    std::string text;
    std::getline(f, text);
    CHECK(text == "keep me");
  }
  SECTION("output is a directory of something else") {
    fs::create_directories(dir / "mine");
    { std::ofstream(dir / "mine" / "notes.txt") << "x"; }
    CHECK(test::sh(kBin + "/detect -q -i " + q(dir / "tile.pcd") + " -o " + q(dir / "mine"), dir / "err.txt",
                   &err) == 1);
    CHECK(err.find("refusing") != std::string::npos);
    CHECK(fs::exists(dir / "mine" / "notes.txt"));
  }
  SECTION("--voxel 1e-6 names the option (exit 2)") {
    CHECK(test::sh(kBin + "/detect -q --voxel 1e-6 -i " + q(dir / "tile.pcd") + " -o " + q(dir / "out"),
                   dir / "err.txt", &err) == 2);
    CHECK(err.find("--voxel must be in [1 mm, 100 m]") != std::string::npos);
  }
  SECTION("no output") {
    CHECK(test::sh(kBin + "/detect -q -i " + q(dir / "tile.pcd"), dir / "err.txt", &err) == 2);
  }
}

TEST_CASE("detect: bad and unusual input") {
  const fs::path dir = test::fresh_dir("detect", "cli_bad_input");
  detect_test::TileSpec s = small_scene();
  formats::write_pcd(detect_test::make_tile(s), (dir / "tile.pcd").string());
  std::string err;
  SECTION("an empty tile") {
    formats::PointCloud empty;
    empty.add("x", formats::kFloat64);
    empty.add("y", formats::kFloat64);
    empty.add("z", formats::kFloat64);
    formats::write_pcd(empty, (dir / "empty.pcd").string());
    CHECK(test::sh(kBin + "/detect -q -i " + q(dir / "empty.pcd") + " -o " + q(dir / "out"), dir / "err.txt",
                   &err) == 1);
    CHECK(err.find("empty.pcd: the tile has no points") != std::string::npos);
    CHECK(!fs::exists(dir / "out"));
    CHECK(entries(dir) == std::vector<std::string>{"empty.pcd", "err.txt", "tile.pcd"});
  }
  SECTION("float32 coordinates at UTM magnitudes") {
    s.float64 = false;
    formats::write_pcd(detect_test::make_tile(s), (dir / "utm32.pcd").string());
    CHECK(test::sh(kBin + "/detect -q -i " + q(dir / "utm32.pcd") + " -o " + q(dir / "out"), dir / "err.txt",
                   &err) == 1);
    CHECK(err.find("utm32.pcd: coordinate x is stored as float32") != std::string::npos);
    CHECK(!fs::exists(dir / "out"));
  }
  SECTION("a LAZ file is read like LAS (this one is too large a tile)") {
    const std::string laz = std::string(CANOPY_SOURCE_DIR) + "/tests/las/data/simple.laz";
    CHECK(test::sh(kBin + "/detect -q --cell 0.5 -i " + q(laz) + " -o " + q(dir / "out"), dir / "err.txt",
                   &err) == 1);
    CHECK(err.find("simple.laz: the tile spans 3363 m x 4636 m") != std::string::npos);
    CHECK(!fs::exists(dir / "out"));
  }
  SECTION("a tile of only vegetation (no ground returns)") {
    detect_test::TileSpec v;
    v.half_extent = 15;
    v.trees = {{5, 6, 3.0, 5.0, 11.0, 0.2}, {-8, 2, 2.5, 4.0, 9.0, 0.15}, {0, -7, 4, 6, 12, 0.3}};
    v.bushes = {{10, -5, 1.0, 0.2, 1.6}, {-5, -12, 1.5, 0.3, 2.5}};
    formats::PointCloud all = detect_test::make_tile(v);
    std::vector<std::size_t> keep;
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (all.col("label")[i] == formats::kLabelFoliage) keep.push_back(i);
    }
    formats::write_pcd(all.select(keep), (dir / "veg.pcd").string());
    CHECK(test::sh(kBin + "/detect -q -i " + q(dir / "veg.pcd") + " -o " + q(dir / "out"), dir / "err.txt",
                   &err) == 1);
    CHECK(err.find("veg.pcd: found ground in only") != std::string::npos);
    CHECK(!fs::exists(dir / "out"));
  }
  SECTION("a tile of only ground: zero candidates, exit 0") {
    detect_test::TileSpec g;
    g.half_extent = 10;
    g.noise = 0.008;
    formats::write_pcd(detect_test::make_tile(g), (dir / "ground.pcd").string());
    CHECK(test::sh(kBin + "/detect -q -i " + q(dir / "ground.pcd") + " -o " + q(dir / "out"), dir / "err.txt",
                   &err) == 0);
    CHECK(read_json(dir / "out" / "index.json")["candidates"].empty());
  }
}

TEST_CASE("detect: LAS tiles") {
  const fs::path dir = test::fresh_dir("detect", "cli_las_input");
  const detect_test::TileSpec s = small_scene();
  std::string err;
  SECTION("a LAS tile at UTM coordinates gives the same candidates as the PCD tile") {
    const formats::PointCloud t = detect_test::make_tile(s);
    formats::write_pcd(t, (dir / "t.pcd").string());
    formats::write_points(t, (dir / "t.las").string());
    REQUIRE(test::sh(kBin + "/detect -q --no-classes -i " + q(dir / "t.pcd") + " -o " + q(dir / "a"),
                     dir / "err.txt", &err) == 0);
    REQUIRE(test::sh(kBin + "/detect -q --no-classes -i " + q(dir / "t.las") + " -o " + q(dir / "b"),
                     dir / "err.txt", &err) == 0);
    const auto a = read_json(dir / "a" / "index.json")["candidates"];
    const auto b = read_json(dir / "b" / "index.json")["candidates"];
    REQUIRE(a.size() == b.size());
    REQUIRE(a.size() >= 1);
    for (std::size_t i = 0; i < a.size(); ++i) {
      // LAS stores 1 mm integers: centres agree to a few mm.
      CHECK(std::abs(a[i]["centre"][0].get<double>() - b[i]["centre"][0].get<double>()) < 0.01);
      CHECK(std::abs(a[i]["centre"][1].get<double>() - b[i]["centre"][1].get<double>()) < 0.01);
    }
  }
  SECTION("a LAS tile whose georeferencing says feet: a warning naming the unit") {
    // perm-1.2_0.las declares metres (GeoTIFF key 3076 ProjLinearUnits = 9001): no warning;
    // the same file with the key set to 9002 (foot): a warning.
    const std::string src = std::string(CANOPY_SOURCE_DIR) + "/tests/las/data/perm-1.2_0.las";
    std::string bytes;
    {
      std::ifstream f(src, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    }
    const std::string metre("\x04\x0c\x00\x00\x01\x00\x29\x23", 8);  // 3076, 0, 1, 9001 (little-endian)
    const std::size_t at = bytes.find(metre);
    REQUIRE(at != std::string::npos);
    CHECK(test::sh(kBin + "/detect --no-classes -i " + q(src) + " -o " + q(dir / "m"), dir / "err.txt",
                   &err) <= 1);
    CHECK(err.find("warning") == std::string::npos);
    bytes[at + 6] = '\x2a';  // 9002 = foot
    { std::ofstream(dir / "feet.las", std::ios::binary) << bytes; }
    CHECK(test::sh(kBin + "/detect --no-classes -i " + q(dir / "feet.las") + " -o " + q(dir / "ft"),
                   dir / "err.txt", &err) <= 1);
    CHECK(err.find("feet.las: its georeferencing gives the coordinates in foot (0.3048 m) (GeoTIFF key "
                   "ProjLinearUnits = 9002)") != std::string::npos);
    // The warning goes into the index too ("warnings"), for collect to relay (stop 70); the
    // metre tile's index has no such member.
    REQUIRE(fs::exists(dir / "ft" / "index.json"));
    const Json warnings = read_json(dir / "ft" / "index.json")["warnings"];
    REQUIRE(warnings.is_array());
    bool feet = false;
    for (const auto& w : warnings) {
      feet = feet || w.get<std::string>().find(
                         "feet.las: its georeferencing gives the coordinates in foot "
                         "(0.3048 m)") != std::string::npos;
    }
    CHECK(feet);
    REQUIRE(fs::exists(dir / "m" / "index.json"));
    CHECK_FALSE(read_json(dir / "m" / "index.json").contains("warnings"));
    // The detect phase's line is said once: "detect: density ...", not "detect: detect: density ...".
    CHECK(err.find("detect: density ") != std::string::npos);
    CHECK(err.find("detect: detect:") == std::string::npos);
  }
  SECTION("the CRS the LAS file records goes into the index; a tile without one has no crs member") {
    const std::string las = formats::serialize_las(box_tile(), "box");
    const std::string wkt = R"(PROJCS["RGF93 v1 / Lambert-93",GEOGCS["RGF93 v1",AUTHORITY["EPSG","4171"]],)"
                            R"(UNIT["metre",1,AUTHORITY["EPSG","9001"]],AUTHORITY["EPSG","2154"]])";
    test::write_file((dir / "none.las").string(), las);
    test::write_file((dir / "wkt.las").string(), las_test::with_vlr(las, "LASF_Projection", 2112, wkt));
    test::write_file((dir / "keys.las").string(),
                     las_test::with_vlr(las, "LASF_Projection", 34735, las_test::geokeys({{3072, 28992}})));
    test::write_file((dir / "bad.las").string(),
                     las_test::with_vlr(las, "LASF_Projection", 2112, wkt.substr(0, 40)));
    formats::write_pcd(box_tile(), (dir / "box.pcd").string());
    auto index_of = [&](const std::string& tile) {
      REQUIRE(test::sh(kBin + "/detect --no-classes -i " + q(dir / tile) + " -o " + q(dir / (tile + ".out")),
                       dir / "err.txt", &err) == 0);
      return read_json(dir / (tile + ".out") / "index.json");
    };
    Json j = index_of("wkt.las");
    CHECK(j["crs"] == "EPSG:2154");
    CHECK(j["crs_from"] == "LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154");
    CHECK(j["candidates"].size() == 1);
    CHECK(err.find("wkt.las: CRS EPSG:2154 (LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154)") !=
          std::string::npos);
    j = index_of("keys.las");
    CHECK(j["crs"] == "EPSG:28992");
    CHECK(j["crs_from"] == "LASF_Projection 34735 (GeoTIFF keys): ProjectedCSTypeGeoKey 28992");
    for (const char* tile : {"none.las", "box.pcd"}) {
      j = index_of(tile);
      CHECK_FALSE(j.contains("crs"));
      CHECK_FALSE(j.contains("crs_from"));
      CHECK(err.find("CRS") == std::string::npos);
    }
    // A WKT cut short: no CRS, one warning line, the tile detected as the others.
    j = index_of("bad.las");
    CHECK_FALSE(j.contains("crs"));
    CHECK(j["candidates"].size() == 1);
    CHECK(err.find("bad.las: LASF_Projection 2112 (OGC WKT): the WKT is not well-formed (byte 40: ") !=
          std::string::npos);
    CHECK(err.find("no CRS in the index (give collect --crs, make CRS=EPSG:<code>)") != std::string::npos);
  }
  SECTION("a LAS tile on standard input or from a FIFO: its CRS and its unit all the same") {
    // Until stop 68 detect read the header again from the path, which "-" and a FIFO cannot
    // give: no CRS, no feet warning, and nothing said. The reader now hands its header back.
    const std::string las = formats::serialize_las(box_tile(), "box");
    const std::string wkt =
        R"w(PROJCS["NAD83 / California zone 5 (ftUS)",GEOGCS["NAD83",AUTHORITY["EPSG","4269"]],)w"
        R"w(UNIT["US survey foot",0.3048006096012192,AUTHORITY["EPSG","9003"]],)w"
        R"w(AUTHORITY["EPSG","2229"]])w";
    test::write_file((dir / "ft.las").string(), las_test::with_vlr(las, "LASF_Projection", 2112, wkt));
    REQUIRE(test::sh(kBin + "/detect --no-classes -i - -o " + q(dir / "stdin.out") + " < " + q(dir / "ft.las"),
                     dir / "err.txt", &err) == 0);
    Json j = read_json(dir / "stdin.out" / "index.json");
    CHECK(j["crs"] == "EPSG:2229");
    CHECK(j["crs_from"] == "LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2229");
    CHECK(j["candidates"].size() == 1);
    CHECK(err.find("<stdin>: CRS EPSG:2229 (LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2229)") !=
          std::string::npos);
    CHECK(
        err.find("<stdin>: its georeferencing gives the coordinates in US survey foot (0.3048006096 m) (WKT "
                 "UNIT[\"US survey foot\",0.3048006096012192,AUTHORITY[\"EPSG\",\"9003\"]])") !=
        std::string::npos);
    const fs::path fifo = dir / "fifo";
    test::write_file(
        (dir / "keys_ft.las").string(),
        las_test::with_vlr(las, "LASF_Projection", 34735, las_test::geokeys({{3072, 2229}, {3076, 9002}})));
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    REQUIRE(test::sh("{ cat " + q(dir / "keys_ft.las") + " > " + q(fifo) + " & " + kBin +
                         "/detect --no-classes -i " + q(fifo) + " -o " + q(dir / "fifo.out") + "; }",
                     dir / "err.txt", &err) == 0);
    j = read_json(dir / "fifo.out" / "index.json");
    CHECK(j["crs"] == "EPSG:2229");
    CHECK(j["crs_from"] == "LASF_Projection 34735 (GeoTIFF keys): ProjectedCSTypeGeoKey 2229");
    CHECK(err.find("fifo: its georeferencing gives the coordinates in foot (0.3048 m) (GeoTIFF key "
                   "ProjLinearUnits = 9002)") != std::string::npos);
  }
}

// A rangetrace sedan (realistic surfaces) posed in a wide ground crop at UTM coordinates, a
// tree beside it: detect finds it, and fitvox | cocone | ncut | gmatch recognise the candidate
// against a sedan/tank modelbase built as in the smoke test.
TEST_CASE("the existing chain runs on a candidate unchanged") {
  const fs::path dir = test::fresh_dir("detect", "chain");
  const std::string rt = kBin + "/rangetrace -q --scene unoccluded ";
  std::string err;
  REQUIRE(test::sh(rt +
                       "--model sedan --seed 31 --heading 35deg --position 2,-1 --crop-length 24m "
                       "--crop-width 24m --crop-height 12m -o " +
                       q(dir / "scan.pcd"),
                   dir / "err.txt", &err) == 0);
  formats::PointCloud scan = formats::read_pcd((dir / "scan.pcd").string());
  // To UTM magnitudes in float64.
  for (const char* a : {"x", "y", "z"}) {
    auto& col = scan.add(a, formats::kFloat64);
    const double off = a[0] == 'x' ? 612345.0 : a[0] == 'y' ? 5012345.0 : 350.0;
    for (double& v : col) v += off;
  }
  formats::write_pcd(scan, (dir / "tile.pcd").string());
  REQUIRE(test::sh(kBin + "/detect -q -i " + q(dir / "tile.pcd") + " -o " + q(dir / "cands"), dir / "err.txt",
                   &err) == 0);
  const Json j = read_json(dir / "cands" / "index.json");
  REQUIRE(j["candidates"].size() == 1);
  const auto& c = j["candidates"][0];
  CHECK(c["centre"][0].get<double>() == Approx(612345.0 + 2).margin(0.3));
  CHECK(c["centre"][1].get<double>() == Approx(5012345.0 - 1).margin(0.3));
  CHECK(c["centre"][2].get<double>() == Approx(350.0).margin(0.05));
  const double heading = c["heading"].get<double>() * 180 / canopy::common::kPi;
  CHECK(std::min(std::abs(heading - 35), std::abs(std::abs(heading - 35) - 180)) < 5);

  fs::create_directories(dir / "mb");
  for (const std::string m : {"sedan", "tank"}) {
    REQUIRE(test::sh(rt + "--model " + m + " --seed 11 | " + kBin + "/fitvox -q | " + kBin + "/cocone -q | " +
                         kBin + "/ncut -q --seed 11 -o " + q(dir / "mb" / (m + ".json")),
                     dir / "err.txt", &err) == 0);
  }
  const fs::path cand = dir / "cands" / c["file"].get<std::string>();
  REQUIRE(test::sh(kBin + "/fitvox -q -i " + q(cand) + " | " + kBin + "/cocone -q | " + kBin +
                       "/ncut -q --seed 11 | " + kBin + "/gmatch --modelbase " + q(dir / "mb") + " -o " +
                       q(dir / "match.json"),
                   dir / "err.txt", &err) == 0);
  INFO(err);
  const Json match = read_json(dir / "match.json");
  CHECK(match["models"][0]["model"] == "sedan");
}

// issue 25 (../shared/data/malformed/round3/replay.sh cases 3 and 11, and item 10): -o replaces
// only what detect can prove it wrote; missing parents are not created; a symbolic link to a
// directory is followed; leftovers of killed runs are removed by the next run.
TEST_CASE("detect -o: only a previous detect output is replaced") {
  const fs::path dir = test::fresh_dir("detect", "cli_output_rule");
  formats::write_pcd(box_tile(), (dir / "box.pcd").string());
  const std::string detect = kBin + "/detect -q -i " + q(dir / "box.pcd") + " -o ";
  std::string err;
  SECTION("replay case 3: a directory that merely holds a file called index.json") {
    const fs::path web = dir / "webapp";
    fs::create_directories(web / "src");
    { std::ofstream(web / "index.json") << "{\"name\": \"my-web-app\"}"; }
    { std::ofstream(web / "app.js") << "precious"; }
    { std::ofstream(web / "src" / "main.c") << "code"; }
    CHECK(test::sh(detect + q(web), dir / "err.txt", &err) == 1);
    INFO(err);
    CHECK(err.find("detect: error: " + web.string() + ": refusing to replace it") != std::string::npos);
    CHECK(err.find("it holds app.js, index.json, src/") != std::string::npos);
    CHECK(err.find("detect: read") == std::string::npos);  // refused before the work
    CHECK(entries(web) == std::vector<std::string>{"app.js", "index.json", "src"});
    CHECK(fs::exists(web / "src" / "main.c"));
  }
  SECTION("replay case 3: the input tile and a user's file inside a previous output") {
    const fs::path io = dir / "io";
    REQUIRE(test::sh(detect + q(io), dir / "err.txt", &err) == 0);
    const std::string index = read_json(io / "index.json").dump();
    fs::copy_file(dir / "box.pcd", io / "tile.pcd");
    { std::ofstream(io / "NOTES.txt") << "notes"; }
    CHECK(test::sh(kBin + "/detect -q -i " + q(io / "tile.pcd") + " -o " + q(io), dir / "err.txt", &err) == 1);
    INFO(err);
    CHECK(err.find("it holds the input tile " + fs::canonical(io / "tile.pcd").string()) != std::string::npos);
    CHECK(err.find("NOTES.txt, tile.pcd, which detect did not write") != std::string::npos);
    CHECK(entries(io) == std::vector<std::string>{"NOTES.txt", "c0001.pcd", "classes.ply", "index.json",
                                                  "manifest.json", "tile.pcd"});
    CHECK(read_json(io / "index.json").dump() == index);
  }
  SECTION("a missing parent directory is refused, not created (as every other tool does)") {
    CHECK(test::sh(detect + q(dir / "no" / "such" / "cands"), dir / "err.txt", &err) == 1);
    CHECK(err.find("directory '" + (dir / "no" / "such").string() + "' does not exist") != std::string::npos);
    CHECK(!fs::exists(dir / "no"));
  }
  SECTION("a symbolic link to a directory: the directory is written, the link stays") {
    fs::create_directories(dir / "real");
    fs::create_directory_symlink("real", dir / "link");
    for (const std::string o : {"link", "link/"}) {
      INFO("-o " << o);
      REQUIRE(test::sh(detect + q(dir / o), dir / "err.txt", &err) == 0);
      CHECK(fs::is_symlink(dir / "link"));
      CHECK(read_json(dir / "real" / "index.json")["candidates"].size() == 1);
    }
    CHECK(entries(dir) == std::vector<std::string>{"box.pcd", "err.txt", "link", "real"});
  }
  SECTION("replay case 11: leftovers of killed runs are removed by the next run") {
    const fs::path out = dir / "cands";
    REQUIRE(test::sh(detect + q(out), dir / "err.txt", &err) == 0);
    // What killed runs of this and of older detects left: a partial temporary directory (its
    // marker), the previous output moved aside (older detects: no manifest), an empty one.
    fs::create_directories(dir / ".cands.tmp1000001");
    { std::ofstream(dir / ".cands.tmp1000001" / ".detect-partial"); }
    { std::ofstream(dir / ".cands.tmp1000001" / "c0001.pcd") << "half"; }
    fs::copy(out, dir / ".cands.old1000002");
    fs::remove(dir / ".cands.old1000002" / "manifest.json");
    fs::create_directories(dir / ".cands.tmp1000003");
    REQUIRE(test::sh(detect + q(out), dir / "err.txt", &err) == 0);
    CHECK(entries(dir) == std::vector<std::string>{"box.pcd", "cands", "err.txt"});
  }
}

TEST_CASE("detect: a few points spread wide (replay case 8)") {
  const fs::path dir = test::fresh_dir("detect", "cli_sparse");
  const std::string data = std::string(CANOPY_SOURCE_DIR) + "/tests/detect/data/";
  std::string err;
  // 10 points over 2200 m x 2200 m, and on a 9000 km line: > 600 s and 579 s before (1000
  // relaxation sweeps over up to 2e7 DTM cells), now refused at once. With 0.5 m cells as given:
  // the density rule's default cell for 10 points is 2 m (detect.md §7), the case below.
  for (const std::string f : {"detect-2200m-10pts.pcd", "detect-line-9000km-10pts.pcd"}) {
    INFO(f);
    CHECK(test::sh(kBin + "/detect --cell 0.5 -i " + q(data + f) + " -o " + q(dir / "out"), dir / "err.txt",
                   &err) == 1);
    INFO(err);
    CHECK(err.find(data + f + ": its 10 points spread over") != std::string::npos);
    CHECK(err.find("crop the tile to where its points are, or raise --cell") != std::string::npos);
    CHECK(!fs::exists(dir / "out"));
  }
  // The same 10 points with 2 m cells (1.2e6 cells): a result, 0 candidates.
  REQUIRE(test::sh(kBin + "/detect --cell 2 -i " + q(data + "detect-2200m-10pts.pcd") + " -o " + q(dir / "out"),
                   dir / "err.txt", &err) == 0);
  const Json j = read_json(dir / "out" / "index.json");
  CHECK(j["candidates"].empty());
  CHECK(j["ground"]["cells"] == 1101 * 1101);
}

TEST_CASE("detect --trajectory: the candidates of a tile without sensor columns carry them") {
  // The box tile as a sensor-mode render has it: gps_time, no sensor_x/y/z; the sensor flies
  // along +x at 100 m over y = -50 (so every point sees it up and toward -y).
  const fs::path dir = test::fresh_dir("detect", "cli_trajectory");
  formats::PointCloud tile = box_tile();
  auto& t = tile.add("gps_time", formats::kFloat64);
  for (std::size_t i = 0; i < tile.size(); ++i) t[i] = tile.col("x")[i] / 50.0;  // 50 m/s
  formats::write_pcd(tile, (dir / "tile.pcd").string());
  formats::Trajectory traj;
  traj.samples.push_back({0, 0, -50, 100, 0, 0, 0});
  traj.samples.push_back({2, 100, -50, 100, 0, 0, 0});
  formats::write_trajectory(traj, (dir / "tile.traj").string());
  std::string err;
  REQUIRE(test::sh(kBin + "/detect -i " + q(dir / "tile.pcd") + " -o " + q(dir / "cands") + " --trajectory " +
                       q(dir / "tile.traj"),
                   dir / "err.txt", &err) == 0);
  INFO(err);
  const Json j = read_json(dir / "cands" / "index.json");
  REQUIRE(j["candidates"].size() == 1);
  const auto& c = j["candidates"][0];
  const formats::PointCloud cloud = formats::read_pcd((dir / "cands" / c["file"].get<std::string>()).string());
  REQUIRE(cloud.has("sensor_x"));
  REQUIRE(cloud.has("sensor_z"));
  // Back in the tile's frame (the transform's rotation), each direction points at the sensor at
  // the point's time: S(t) = (50 t, -50, 100).
  Eigen::Matrix3d r;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) r(a, b) = c["transform"][a][b].get<double>();
  Eigen::Vector3d o(c["transform"][0][3].get<double>(), c["transform"][1][3].get<double>(),
                    c["transform"][2][3].get<double>());
  double worst = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = r * Eigen::Vector3d(cloud.col("x")[i], cloud.col("y")[i], cloud.col("z")[i]) + o;
    const Eigen::Vector3d d =
        r * Eigen::Vector3d(cloud.col("sensor_x")[i], cloud.col("sensor_y")[i], cloud.col("sensor_z")[i]);
    const Eigen::Vector3d want = (Eigen::Vector3d(50 * cloud.col("gps_time")[i], -50, 100) - p).normalized();
    worst = std::max(worst, (d - want).norm());
  }
  CHECK(worst < 1e-4);
  // Without --trajectory: no columns (the candidates carry what the tile has).
  REQUIRE(test::sh(kBin + "/detect -i " + q(dir / "tile.pcd") + " -o " + q(dir / "plain"), dir / "err2.txt",
                   &err) == 0);
  const Json k = read_json(dir / "plain" / "index.json");
  REQUIRE(k["candidates"].size() == 1);
  CHECK(!formats::read_pcd((dir / "plain" / k["candidates"][0]["file"].get<std::string>()).string())
             .has("sensor_x"));
  // A tile without gps_time cannot use a trajectory: an error naming the tile.
  formats::write_pcd(box_tile(), (dir / "bare.pcd").string());
  CHECK(test::sh(kBin + "/detect -i " + q(dir / "bare.pcd") + " -o " + q(dir / "bare") + " --trajectory " +
                     q(dir / "tile.traj"),
                 dir / "err3.txt", &err) != 0);
  CHECK(err.find("gps_time") != std::string::npos);
}

TEST_CASE("detect --config: the density ladder's parameters (end-gap 1) and their ablation (end-gap 0)") {
  // mk/density.mk gives the class-level rungs share/params/detect-ladder.ini and their detect
  // ablation bench/density/detect-end-gap-0.ini: each reaches detect's parameters (the index's
  // provenance), and detect's default is the ablation's value.
  const fs::path dir = test::fresh_dir("detect", "cli_ladder_config");
  formats::write_pcd(detect_test::make_tile(small_scene()), (dir / "tile.pcd").string());
  const std::string src = CANOPY_SOURCE_DIR;
  const auto end_gap = [&](const std::string& config, const std::string& name) {
    std::string err;
    const fs::path out = dir / name;
    const int rc =
        test::sh(kBin + "/detect --no-classes" + (config.empty() ? "" : " --config " + q(src + "/" + config)) +
                     " -i " + q(dir / "tile.pcd") + " -o " + q(out),
                 dir / (name + ".err"), &err);
    INFO(err);
    REQUIRE(rc == 0);
    return read_json(out / "index.json")["provenance"]["parameters"]["end-gap"].get<std::string>();
  };
  CHECK(end_gap("share/params/detect-ladder.ini", "ladder") == "1");
  CHECK(end_gap("bench/density/detect-end-gap-0.ini", "ablation") == "0");
  CHECK(end_gap("", "default") == "0");
}
