// collect: hand-written candidates index and verdicts at UTM coordinates -> detections.json
// and GeoJSON, checked against hand-computed poses and footprints.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "canopy/common/math.h"
#include "canopy/documents/detections.h"
#include "canopy/formats/pcd.h"
#include "classify/classify.h"
#include "collect/collect.h"
#include "support/cli.h"

using namespace canopy;
using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

namespace {

const double E = 500000.123, N = 5400000.456;  // UTM magnitudes: 1 mm must survive

Json rows(double heading_deg, double x, double y, double z) {
  const double c = std::cos(heading_deg * common::kPi / 180), s = std::sin(heading_deg * common::kPi / 180);
  return Json::array({Json::array({c, -s, 0.0, x}), Json::array({s, c, 0.0, y}),
                      Json::array({0.0, 0.0, 1.0, z}), Json::array({0.0, 0.0, 0.0, 1.0})});
}

Json flat(double heading_deg, double x, double y, double z) {
  Json f = Json::array();
  for (const auto& r : rows(heading_deg, x, y, z)) {
    for (const auto& v : r) f.push_back(v);
  }
  return f;
}

// verify's members of every canopy.verdict (documents/verdict.h reads them all).
Json pose_member(const Json& matrix) { return matrix.is_null() ? matrix : Json{{"matrix", matrix}}; }
Json provenance() {
  return Json{{"tool", "test"}, {"version", "0"}, {"parameters", Json::object()}, {"inputs", Json::array()}};
}

// A verdict as verify writes it for the candidate's samples (`candidate`: verify --points):
// with a model, its one hypothesis (chosen) carries the pose.
Json verdict(const std::string& candidate, const char* model, double confidence, const Json& pose,
             const Json& pose_tile) {
  Json hypotheses = Json::array();
  if (model) {
    hypotheses.push_back(Json{{"model", model},
                              {"gmatch_rank", 1},
                              {"gmatch_score", 0.5},
                              {"start", "pairs"},
                              {"flipped", false},
                              {"pose", pose_member(pose.is_null() ? pose_tile : pose)},
                              {"pose_tile", pose_member(pose_tile)},
                              {"fit_rms", 0.01},
                              {"explained", 0.9},
                              {"free_space_violation", 0.0},
                              {"score", 0.9},
                              {"flip_score", 0.1}});
  }
  return Json{{"format", "canopy.verdict"},
              {"version", 1},
              {"provenance", provenance()},
              {"candidate", candidate},
              {"model", model ? Json(model) : Json(nullptr)},
              {"confidence", confidence},
              {"pose", pose_member(pose)},
              {"pose_tile", pose_member(pose_tile)},
              {"transform", nullptr},
              {"chosen", model ? 0 : -1},
              {"hypotheses", hypotheses}};
}

void write(const fs::path& p, const std::string& text) { test::write_file(p, text); }

Json read_json(const fs::path& p) {
  std::ifstream f(p.string());
  return Json::parse(f);
}

// Three candidates: c0001 a sedan (verify gave pose_tile), c0002 none, c0003 a tank whose
// verdict has only the candidate-frame pose (collect composes it with the index transform).
fs::path tile(const std::string& name) {
  const fs::path dir = test::fresh_dir("collect", name);
  const fs::path cands = dir / "cands";
  Json index{
      {"format", "canopy.candidates"},
      {"version", 1},
      {"tile", "tile.pcd"},
      {"candidates",
       {{{"id", "c0001"}, {"transform", rows(0, E + 10, N + 10, 100)}, {"length", 5.0}, {"width", 2.0}},
        {{"id", "c0002"}, {"transform", rows(0, E + 5, N + 25, 100)}, {"length", 3.0}, {"width", 2.0}},
        {{"id", "c0003"}, {"transform", rows(90, E + 20, N + 20, 100)}, {"length", 6.0}, {"width", 3.0}}}}};
  write(cands / "index.json", index.dump());
  // c0001: pose_tile heading 30 at (E + 10.25, N + 10.125, 100.5); its candidate pose is
  // deliberately inconsistent (identity) to show pose_tile is used as given.
  write(cands / "c0001" / "verdict.json", verdict((cands / "c0001" / "samples.pcd").string(), "sedan", 0.9,
                                                  flat(0, 0, 0, 0), flat(30, E + 10.25, N + 10.125, 100.5))
                                              .dump());
  write(cands / "c0002" / "verdict.json",
        verdict((cands / "c0002" / "samples.pcd").string(), nullptr, 0.7, nullptr, nullptr).dump());
  // c0003: model -> candidate = Rz(180) + (0.5, 0, 0); candidate -> tile = Rz(90) + (E+20, N+20, 100):
  // model -> tile = Rz(270) + (E + 20, N + 20.5, 100), heading -90.
  write(cands / "c0003" / "verdict.json",
        verdict((cands / "c0003" / "samples.pcd").string(), "tank", 0.8, flat(180, 0.5, 0, 0), nullptr).dump());
  return dir;
}

std::string bin() { return std::string(CANOPY_BIN_DIR) + "/collect"; }

}  // namespace

TEST_CASE("euler angles and products of 4 x 4 matrices") {
  collect::Matrix a{}, b{};
  const Json ja = flat(90, 1, 2, 3), jb = flat(45, 1, 0, 0);
  for (int i = 0; i < 16; ++i) {
    a[i] = ja[i].get<double>();
    b[i] = jb[i].get<double>();
  }
  const collect::Matrix p = collect::multiply(a, b);
  CHECK(p[3] == Approx(1));  // Rz(90) (1, 0, 0) + (1, 2, 3) = (1, 3, 3)
  CHECK(p[7] == Approx(3));
  CHECK(p[11] == Approx(3));
  CHECK(collect::euler_degrees(p)[0] == Approx(135));
  CHECK(collect::euler_degrees(a)[1] == Approx(0).margin(1e-12));
}

TEST_CASE("collect: detections, none counted, poses and footprints at UTM coordinates") {
  const fs::path dir = tile("basic");
  // A modelbase sedan surface: vehicle points x in [-2, 2], y in [-1, 1]; a label-2 point far
  // away that must not widen the box. No tank surface: its footprint is the candidate's.
  formats::PointCloud mb;
  auto& x = mb.add("x");
  auto& y = mb.add("y");
  auto& z = mb.add("z");
  auto& l = mb.add("label", formats::kUint32);
  for (const auto& p :
       {std::array<double, 4>{-2, -1, 0, 1}, {2, 1, 1.4, 1}, {0.5, 0.2, 0.8, 1}, {50, 50, 0, 2}}) {
    x.push_back(p[0]);
    y.push_back(p[1]);
    z.push_back(p[2]);
    l.push_back(p[3]);
  }
  mb.resize(4);
  fs::create_directories(dir / "mb");
  formats::write_pcd(mb, (dir / "mb" / "sedan.pcd").string());

  std::string err;
  const std::string cmd = bin() + " -q -i " + (dir / "cands" / "index.json").string() + " -o " +
                          (dir / "detections.json").string() + " --geojson " + (dir / "d.geojson").string() +
                          " --modelbase " + (dir / "mb").string() + " --crs EPSG:32633";
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  const Json d = read_json(dir / "detections.json");
  CHECK(d["format"] == "canopy.detections");
  CHECK(d["version"] == 2);
  CHECK(d["candidates"] == 3);
  CHECK(d["found"] == 2);
  CHECK(d["none"] == 1);
  CHECK(d["crs"] == "EPSG:32633");
  REQUIRE(d["detections"].size() == 2);
  REQUIRE(d["rejected"].size() == 1);
  CHECK(d["rejected"][0]["candidate"] == "c0002");

  const Json& s = d["detections"][0];
  CHECK(s["candidate"] == "c0001");
  CHECK(s["level"] == "model");
  CHECK(s["model"] == "sedan");
  CHECK(s["confidence"].get<double>() == Approx(0.9));
  CHECK(s["pose"]["x"].get<double>() == Approx(E + 10.25).margin(1e-6));
  CHECK(s["pose"]["y"].get<double>() == Approx(N + 10.125).margin(1e-6));
  CHECK(s["pose"]["z"].get<double>() == Approx(100.5).margin(1e-9));
  CHECK(s["pose"]["heading"].get<double>() == Approx(30));
  CHECK(s["footprint_from"] == "model");
  // Corner (2, 1) of the model box turned by 30 degrees.
  const double c30 = std::cos(common::kPi / 6), s30 = std::sin(common::kPi / 6);
  CHECK(s["footprint"][2][0].get<double>() == Approx(E + 10.25 + 2 * c30 - s30).margin(1e-6));
  CHECK(s["footprint"][2][1].get<double>() == Approx(N + 10.125 + 2 * s30 + c30).margin(1e-6));
  // The same surface built from an unlabelled scan (fitvox writes label 0 on every row): no
  // labels, every row bounds the model (stop 70; before: "has no vehicle points (label 1)", exit 1).
  {
    formats::PointCloud bare;
    bare.resize(3);
    bare.add("x") = {-2, 2, 0.5};
    bare.add("y") = {-1, 1, 0.2};
    bare.add("z") = {0, 1.4, 0.8};
    bare.add("label", formats::kUint32) = {0, 0, 0};
    fs::create_directories(dir / "mb0");
    formats::write_pcd(bare, (dir / "mb0" / "sedan.pcd").string());
    const std::string cmd0 = bin() + " -q -i " + (dir / "cands" / "index.json").string() + " -o " +
                             (dir / "detections0.json").string() + " --modelbase " + (dir / "mb0").string();
    REQUIRE(test::sh(cmd0, dir / "err0.txt", &err) == 0);
    const Json s0 = read_json(dir / "detections0.json")["detections"][0];
    CHECK(s0["footprint_from"] == "model");
    CHECK(s0["footprint"] == s["footprint"]);
  }

  const Json& t = d["detections"][1];
  CHECK(t["candidate"] == "c0003");
  CHECK(t["pose"]["x"].get<double>() == Approx(E + 20).margin(1e-6));
  CHECK(t["pose"]["y"].get<double>() == Approx(N + 20.5).margin(1e-6));
  CHECK(t["pose"]["heading"].get<double>() == Approx(-90));
  CHECK(t["footprint_from"] == "candidate");
  // The 6 x 3 candidate footprint turned by 90 degrees about (E + 20, N + 20), counter-clockwise.
  const double want[4][2] = {{21.5, 17}, {21.5, 23}, {18.5, 23}, {18.5, 17}};
  for (int k = 0; k < 4; ++k) {
    CHECK(t["footprint"][k][0].get<double>() == Approx(E + want[k][0]).margin(1e-6));
    CHECK(t["footprint"][k][1].get<double>() == Approx(N + want[k][1]).margin(1e-6));
  }
}

TEST_CASE("collect: the GeoJSON parses back, rings are closed and counter-clockwise, 1 mm kept") {
  const fs::path dir = tile("geojson");
  std::string err;
  const std::string base = bin() + " -q -i " + (dir / "cands" / "index.json").string() + " -o " +
                           (dir / "detections.json").string() + " --geojson " + (dir / "d.geojson").string();
  REQUIRE(test::sh(base, dir / "err.txt", &err) == 0);
  const Json g = read_json(dir / "d.geojson");
  const Json d = read_json(dir / "detections.json");
  CHECK(g["type"] == "FeatureCollection");
  CHECK_FALSE(g.contains("crs"));  // RFC 7946: no crs member unless --crs is given
  REQUIRE(g["features"].size() == 2);
  for (std::size_t f = 0; f < 2; ++f) {
    const Json& feat = g["features"][f];
    CHECK(feat["type"] == "Feature");
    CHECK(feat["geometry"]["type"] == "Polygon");
    const Json& ring = feat["geometry"]["coordinates"][0];
    REQUIRE(ring.size() == 5);
    CHECK(ring[0] == ring[4]);
    // Shoelace relative to the first corner (products of UTM magnitudes would cancel).
    const double x0 = ring[0][0].get<double>(), y0 = ring[0][1].get<double>();
    double area2 = 0;
    for (int k = 0; k < 4; ++k) {
      area2 += (ring[k][0].get<double>() - x0) * (ring[k + 1][1].get<double>() - y0) -
               (ring[k + 1][0].get<double>() - x0) * (ring[k][1].get<double>() - y0);
    }
    CHECK(area2 > 0);
    // Without a modelbase both footprints are the candidates': 5 x 2 and 6 x 3 m.
    CHECK(area2 / 2 == Approx(f == 0 ? 10 : 18).epsilon(1e-6));
    // Same numbers as detections.json, and the hand-computed ones to 1 mm.
    for (int k = 0; k < 4; ++k) CHECK(ring[k] == d["detections"][f]["footprint"][k]);
    CHECK(feat["properties"]["model"] == d["detections"][f]["model"]);
  }
  const Json& r = g["features"][0]["geometry"]["coordinates"][0];
  CHECK(std::fabs(r[0][0].get<double>() - (E + 7.5)) < 1e-3);
  CHECK(std::fabs(r[0][1].get<double>() - (N + 9)) < 1e-3);
  CHECK(std::fabs(r[2][0].get<double>() - (E + 12.5)) < 1e-3);
  CHECK(std::fabs(r[2][1].get<double>() - (N + 11)) < 1e-3);

  REQUIRE(test::sh(base + " --crs EPSG:25832", dir / "err.txt", &err) == 0);
  const Json g2 = read_json(dir / "d.geojson");
  CHECK(g2["crs"]["properties"]["name"] == "urn:ogc:def:crs:EPSG::25832");
}

TEST_CASE("collect: the tile's CRS from the index when --crs is not given; --crs wins; none stays none") {
  const fs::path dir = tile("tile_crs");
  const fs::path index = dir / "cands" / "index.json";
  Json j = read_json(index);
  const std::string plain = j.dump();
  j["crs"] = "EPSG:2154";
  j["crs_from"] = "LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154";
  write(index, j.dump());
  std::string err;
  const std::string base = bin() + " -i " + index.string() + " -o " + (dir / "detections.json").string() +
                           " --geojson " + (dir / "d.geojson").string();
  REQUIRE(test::sh(base, dir / "err.txt", &err) == 0);
  Json d = read_json(dir / "detections.json"), g = read_json(dir / "d.geojson");
  CHECK(d["crs"] == "EPSG:2154");
  CHECK(d["crs_from"] == "tile: LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154");
  CHECK(g["crs"]["type"] == "name");
  CHECK(g["crs"]["properties"]["name"] == "urn:ogc:def:crs:EPSG::2154");
  CHECK(g["crs_from"] == d["crs_from"]);
  CHECK(err.find("warning") == std::string::npos);
  CHECK(err.find("no CRS") == std::string::npos);

  // An explicit --crs wins over the tile's record; the log says they differ.
  REQUIRE(test::sh(base + " --crs EPSG:25832", dir / "err.txt", &err) == 0);
  d = read_json(dir / "detections.json");
  g = read_json(dir / "d.geojson");
  CHECK(d["crs"] == "EPSG:25832");
  CHECK(d["crs_from"] == "--crs");
  CHECK(g["crs"]["properties"]["name"] == "urn:ogc:def:crs:EPSG::25832");
  CHECK(g["crs_from"] == "--crs");
  CHECK(
      err.find("--crs EPSG:25832 given: used, though the tile's file records EPSG:2154 (LASF_Projection 2112 "
               "(OGC WKT): PROJCS AUTHORITY EPSG 2154)") != std::string::npos);

  // An index without a CRS: null, no crs_from, no GeoJSON member (as before this change).
  write(index, plain);
  REQUIRE(test::sh(base, dir / "err.txt", &err) == 0);
  d = read_json(dir / "detections.json");
  g = read_json(dir / "d.geojson");
  CHECK(d["crs"].is_null());
  CHECK_FALSE(d.contains("crs_from"));
  CHECK_FALSE(g.contains("crs"));
  CHECK_FALSE(g.contains("crs_from"));
  // ... and a note that a GIS would read it as WGS 84 degrees, with the remedy (not with -q).
  CHECK(err.find("d.geojson: no CRS (no --crs, and detect recorded none for the tile): a GIS reads a "
                 "GeoJSON without one as WGS 84 longitude/latitude; give --crs EPSG:<code>") !=
        std::string::npos);

  // An index whose crs is not EPSG:<code> is refused, naming the member.
  j["crs"] = "Lambert-93";
  write(index, j.dump());
  CHECK(test::sh(base, dir / "err.txt", &err) == 1);
  CHECK(err.find("crs must be EPSG:<code>") != std::string::npos);
  // --crs alike: no code 0, no leading zeros (usage, exit 2).
  write(index, plain);
  CHECK(test::sh(base + " --crs EPSG:0", dir / "err.txt", &err) == 2);
  CHECK(test::sh(base + " --crs EPSG:02154", dir / "err.txt", &err) == 2);
  CHECK(err.find("--crs must be EPSG:<code>") != std::string::npos);
}

TEST_CASE("collect: an empty verdict is a failed candidate, counted, not a detection") {
  const fs::path dir = tile("failed");
  write(dir / "cands" / "c0003" / "verdict.json", "");
  std::string err;
  REQUIRE(test::sh(
              bin() + " -q -i " + (dir / "cands" / "index.json").string() + " -o " + (dir / "d.json").string(),
              dir / "err.txt", &err) == 0);
  const Json d = read_json(dir / "d.json");
  CHECK(d["found"] == 1);
  CHECK(d["none"] == 1);
  CHECK(d["failed"] == 1);
  REQUIRE(d["rejected"].size() == 2);
  CHECK(d["rejected"][0]["reason"] == "none");
  CHECK(d["rejected"][1]["reason"] == "failed");
  CHECK(d["rejected"][1]["candidate"] == "c0003");
}

TEST_CASE("collect: empty index gives empty, valid outputs") {
  const fs::path dir = test::fresh_dir("collect", "empty");
  write(dir / "cands" / "index.json", R"({"format":"canopy.candidates","version":1,"candidates":[]})");
  std::string err;
  REQUIRE(test::sh(bin() + " -q -i " + (dir / "cands" / "index.json").string() + " -o " +
                       (dir / "d.json").string() + " --geojson " + (dir / "d.geojson").string(),
                   dir / "err.txt", &err) == 0);
  CHECK(read_json(dir / "d.json")["detections"].empty());
  CHECK(read_json(dir / "d.geojson")["features"].empty());
}

TEST_CASE("collect: a missing or bad verdict is named, nothing is written") {
  const fs::path dir = tile("bad");
  fs::remove(dir / "cands" / "c0003" / "verdict.json");
  const std::string cmd = bin() + " -q -i " + (dir / "cands" / "index.json").string() + " -o " +
                          (dir / "d.json").string() + " --geojson " + (dir / "d.geojson").string();
  std::string err;
  CHECK(test::sh(cmd, dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("c0003/verdict.json"));
  CHECK_FALSE(test::exists(dir / "d.json"));
  CHECK_FALSE(test::exists(dir / "d.geojson"));
  write(dir / "cands" / "c0003" / "verdict.json",
        verdict("cands/c0003/samples.pcd", "tank", 1.5, flat(0, 0, 0, 0), nullptr).dump());
  CHECK(test::sh(cmd, dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("confidence"));
  Json skew = flat(0, 0, 0, 0);
  skew[1] = 0.5;  // not a rotation
  write(dir / "cands" / "c0003" / "verdict.json",
        verdict("cands/c0003/samples.pcd", "tank", 0.5, skew, nullptr).dump());
  CHECK(test::sh(cmd, dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("not a rotation"));
  CHECK_FALSE(test::exists(dir / "d.json"));
  CHECK(test::sh(cmd + " --crs 32633", dir / "err.txt", &err) == 2);
  write(
      dir / "cands" / "index.json",
      R"({"format":"canopy.candidates","version":1,"candidates":[{"id":"../x","transform":[],"length":1,"width":1}]})");
  CHECK(test::sh(cmd, dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("not a plain name"));
}

TEST_CASE("collect: a verdict must be its candidate's, its model a name (round 3, case 13)") {
  const fs::path dir = tile("belong");
  const fs::path cands = dir / "cands";
  const std::string cmd = bin() + " -q -i " + (cands / "index.json").string() + " -o " +
                          (dir / "out.json").string() + " --geojson " + (dir / "out.geojson").string();
  const std::string v1 = (cands / "c0001" / "verdict.json").string();
  Json good = read_json(v1);
  std::string err;
  auto refused = [&](const Json& v, const std::string& why) {
    write(v1, v.dump());
    CHECK(test::sh(cmd, dir / "err.txt", &err) == 1);
    CHECK_THAT(err, Catch::Contains(v1 + ": ") && Catch::Contains(why));
    CHECK_FALSE(test::exists(dir / "out.json"));
    CHECK_FALSE(test::exists(dir / "out.geojson"));
  };
  auto accepted = [&](const Json& v) {
    write(v1, v.dump());
    CHECK(test::sh(cmd, dir / "err.txt", &err) == 0);
    CHECK(read_json(dir / "out.json")["detections"][0]["candidate"] == "c0001");
    fs::remove(dir / "out.json");
    fs::remove(dir / "out.geojson");
  };
  Json v = good;
  // The replay's mutation: another tile's candidate, and a model that is a path.
  v["candidate"] = "some/other/tile/c0042/samples.pcd";
  refused(v, "was written for \"some/other/tile/c0042/samples.pcd\", not for candidate c0001");
  v = good;
  v["model"] = "../../../../../../etc/hostname-is-not-a-model";
  refused(v, "model must be a model name");
  v["model"] = "";
  refused(v, "model must be a model name");
  v = good;
  v["class"] = "a/b";
  refused(v, "class must be a model name");
  v = good;
  v.erase("candidate");
  refused(v, "missing \"candidate\"");
  v["candidate"] = "";
  refused(v, "candidate must name");
  v["candidate"] = "samples.pcd";  // names no candidate
  refused(v, "not for candidate c0001");
  // Another tile's c0001, there to look at: refused; this tile's, spelled in other ways: taken.
  write(dir / "other" / "cands" / "c0001" / "samples.pcd", "x");
  v["candidate"] = (dir / "other" / "cands" / "c0001" / "samples.pcd").string();
  refused(v, "which is not candidate c0001 of this tile");
  write(cands / "c0001" / "samples.pcd", "x");
  v["candidate"] = (cands / "." / "c0001" / "samples.pcd").string();
  accepted(v);
  write(cands / "c0001.pcd", "x");
  v["candidate"] = (cands / "c0001.pcd").string();
  accepted(v);
  v["candidate"] = "c0001.pcd";  // verify run beside the candidates, not from here: only the name tells
  accepted(v);
  accepted(good);
  // A copy of the tile's directory (cp -a orig tile; stop 71): its verdicts name the original's
  // points, which have the same bytes as this tile's: taken (before, refused, so a copied tile
  // could not be re-run with another CRS or TRAJECTORY); the original's with other bytes (another
  // tile's, of either size): still refused.
  const fs::path orig = dir / "orig" / "cands";
  write(orig / "c0001" / "samples.pcd", "x");
  v["candidate"] = (orig / "c0001" / "samples.pcd").string();
  accepted(v);
  write(orig / "c0001.pcd", "x");
  v["candidate"] = (orig / "c0001.pcd").string();
  accepted(v);
  write(orig / "c0001.pcd", "y");
  refused(v, "which is not candidate c0001 of this tile");
  write(orig / "c0001" / "samples.pcd", "xy");
  v["candidate"] = (orig / "c0001" / "samples.pcd").string();
  refused(v, "which is not candidate c0001 of this tile");
}

TEST_CASE("collect --plan: candidate ids and transforms as make variables") {
  const fs::path dir = tile("plan");
  std::string err;
  REQUIRE(test::sh(bin() + " -q -i " + (dir / "cands" / "index.json").string() + " --plan " +
                       (dir / "cands.mk").string(),
                   dir / "err.txt", &err) == 0);
  std::ifstream f((dir / "cands.mk").string());
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string mk = ss.str();
  CHECK_THAT(mk, Catch::Contains("\nTILE_CANDS := c0001 c0002 c0003\n"));
  // The transform round-trips exactly (17 significant digits).
  const std::string key = "\nTILE_TRANSFORM_c0001 := ";
  const auto at = mk.find(key);
  REQUIRE(at != std::string::npos);
  std::stringstream line(mk.substr(at + key.size(), mk.find('\n', at + 1) - at - key.size()));
  std::vector<double> v;
  for (std::string item; std::getline(line, item, ',');) v.push_back(std::stod(item));
  REQUIRE(v.size() == 16);
  CHECK(v[0] == 1);
  CHECK(v[3] == E + 10);
  CHECK(v[7] == N + 10);
  CHECK(v[11] == 100);
  CHECK(v[15] == 1);
  CHECK_THAT(mk, Catch::Contains("\nTILE_TRANSFORM_c0003 := "));
  CHECK(test::sh(bin() + " -q -i " + (dir / "cands" / "index.json").string() + " --plan " +
                     (dir / "cands.mk").string() + " -o " + (dir / "d.json").string(),
                 dir / "err.txt", &err) == 2);
  REQUIRE(test::sh(bin() + " -q -i " + (dir / "cands" / "index.json").string() + " --plan " +
                       (dir / "cands.mk").string() + " --plan-key T_a_1",
                   dir / "err.txt", &err) == 0);
  std::ifstream g((dir / "cands.mk").string());
  std::stringstream gs;
  gs << g.rdbuf();
  CHECK_THAT(gs.str(), Catch::Contains("\nT_a_1_CANDS := c0001 c0002 c0003\n"));
  CHECK(test::sh(bin() + " -q -i " + (dir / "cands" / "index.json").string() + " --plan " +
                     (dir / "cands.mk").string() + " --plan-key 'a b'",
                 dir / "err.txt", &err) == 2);
}

TEST_CASE("collect::run writes the provenance it is given; validate names --crs") {
  collect::Inputs in;
  in.index.name = "idx.json";
  in.index.tile = "tile.pcd";
  collect::Candidate c;
  c.id = "c1";
  c.transform = {1, 0, 0, E, 0, 1, 0, N, 0, 0, 1, 0, 0, 0, 0, 1};
  in.index.candidates = {c};
  collect::Verdict none;
  none.name = "c1/verdict.json";
  none.candidate = "c1/samples.pcd";
  none.confidence = 0.25;
  in.answers = {{none, collect::absent_verdict("c1/class.json")}};
  in.provenance = {"collect", "9.9", {{"crs", ""}, {"plan", ""}}, {"idx.json", "c1/verdict.json"}};
  const collect::Outputs o = collect::run(collect::Params{}, in);
  CHECK(o.found == 0);
  CHECK(o.none == 1);
  const Json d = Json::parse(o.detections);
  CHECK(d["provenance"].dump() ==
        R"({"tool":"collect","version":"9.9","parameters":{"crs":"","plan":""},"inputs":["idx.json","c1/verdict.json"]})");
  CHECK(d["rejected"][0]["confidence"] == 0.25);
  // Both levels said none: the rejection states verify's confidence (fitted on tile candidates
  // for "no vehicle here"), classify's reason; classify's none alone states classify's.
  collect::Verdict cls_none;
  cls_none.name = "c1/class.json";
  cls_none.candidate = "c1.pcd";
  cls_none.level = "class";
  cls_none.reason = "not_vehicle_shape";
  cls_none.confidence = 0.999;
  in.answers = {{none, cls_none}};
  const Json both = Json::parse(collect::run(collect::Params{}, in).detections);
  CHECK(both["rejected"][0]["confidence"] == 0.25);
  CHECK(both["rejected"][0]["reason"] == "not_vehicle_shape");
  in.answers = {{collect::absent_verdict("c1/verdict.json"), cls_none}};
  const Json only = Json::parse(collect::run(collect::Params{}, in).detections);
  CHECK(only["rejected"][0]["confidence"] == 0.999);
  in.answers = {{none, collect::absent_verdict("c1/class.json")}};
  collect::Params p;
  CHECK_NOTHROW(collect::validate(p));
  p.crs = "EPSG:4326";
  CHECK_NOTHROW(collect::validate(p));
  for (const char* bad : {"4326", "EPSG:", "EPSG:1234567", "epsg:4326"}) {
    p.crs = bad;
    CHECK_THROWS_WITH(collect::validate(p), Catch::Contains("--crs"));
  }
}

namespace {

// classify's answer (docs/decisions/classify.md §9) for candidate `id`: a class with its pose
// in the candidate frame, or none with a reason.
Json class_answer(const fs::path& cands, const std::string& id, const char* cls, const char* group,
                  const char* reason, double density, const Json& pose) {
  return Json{
      {"format", "canopy.verdict"},
      {"version", 1},
      {"candidate", (cands / (id + ".pcd")).string()},
      {"level", "class"},
      {"model", nullptr},
      {"class", cls ? Json(cls) : Json(nullptr)},
      {"group", group ? Json(group) : Json(nullptr)},
      {"confidence", 0.6},
      {"reason", reason ? Json(reason) : Json(nullptr)},
      {"detail", reason ? "object density 2.1 points/m² below the 4 points/m² the class level needs" : ""},
      {"pose", pose_member(pose)},
      {"pose_tile", nullptr},
      {"heading_ambiguity_deg", 180},
      {"size", cls ? Json::array({4.5, 1.8, 1.45}) : Json(nullptr)},
      {"density", density},
      {"density_needed", {{"class", 4}, {"model", 370}}},
      {"provenance", provenance()},
      {"transform", nullptr},
      {"chosen", -1},
      {"hypotheses", Json::array()},
      {"nearest_instance", nullptr},
      {"class_score", 0.8},
      {"class_margin", 0.2}};
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p.string());
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

TEST_CASE("collect v2: class answers where the model chain found nothing, failed or did not run") {
  const fs::path dir = tile("levels");
  const fs::path cands = dir / "cands";
  // c0002: the model chain said none, classify a hatchback at (1, 0.5) turned by 90 degrees in
  // the candidate frame (heading 0 at E + 5, N + 25): a class-level detection.
  write(cands / "c0002" / "class.json",
        class_answer(cands, "c0002", "hatchback", "car", nullptr, 30, flat(90, 1, 0.5, 0)).dump());
  // c0003: its model chain failed; classify says too sparse: the rejection carries why.
  write(cands / "c0003" / "verdict.json", "");
  write(cands / "c0003" / "class.json",
        class_answer(cands, "c0003", nullptr, nullptr, "too_sparse", 2.1, nullptr).dump());
  // c0001: the model answer wins over classify's.
  write(cands / "c0001" / "class.json",
        class_answer(cands, "c0001", "suv", "car", nullptr, 900, flat(0, 0, 0, 0)).dump());
  std::string err;
  const std::string cmd = bin() + " -i " + (cands / "index.json").string() + " -o " +
                          (dir / "d.json").string() + " --geojson " + (dir / "d.geojson").string();
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  const Json d = read_json(dir / "d.json");
  CHECK(d["version"] == 2);
  CHECK(d["found"] == 2);
  CHECK(d["by_level"] == Json{{"model", 1}, {"class", 1}});
  CHECK(d["by_reason"] == Json{{"too_sparse", 1}});
  CHECK(d["none"] == 1);  // v1's counts: someone looked (classify) and said none
  CHECK(d["failed"] == 0);
  CHECK(d["density"].is_null());  // an index without detect's density
  CHECK(d["warning"].is_null());  // 1 of 3 rejected; the model chain ran
  CHECK_THAT(err,
             Catch::Contains(
                 "3 candidates: 2 vehicles found (1 model level, 1 class level); rejected: too_sparse 1"));
  REQUIRE(d["detections"].size() == 2);
  CHECK(d["detections"][0]["level"] == "model");
  CHECK(d["detections"][0]["model"] == "sedan");
  const Json& c = d["detections"][1];
  CHECK(c["candidate"] == "c0002");
  CHECK(c["level"] == "class");
  CHECK(c["model"].is_null());
  CHECK(c["class"] == "hatchback");
  CHECK(c["group"] == "car");
  CHECK(c["heading_ambiguity_deg"] == 180.0);
  CHECK(c["density"] == 30.0);
  CHECK(c["size"] == Json{{"length", 4.5}, {"width", 1.8}, {"height", 1.45}});
  CHECK(c["pose"]["x"].get<double>() == Approx(E + 6).margin(1e-6));
  CHECK(c["pose"]["y"].get<double>() == Approx(N + 25.5).margin(1e-6));
  CHECK(c["pose"]["heading"].get<double>() == Approx(90));
  CHECK(c["footprint_from"] == "class");
  // The 4.5 x 1.8 rectangle turned by 90 degrees about (E + 6, N + 25.5), counter-clockwise.
  const double want[4][2] = {{6.9, 23.25}, {6.9, 27.75}, {5.1, 27.75}, {5.1, 23.25}};
  for (int k = 0; k < 4; ++k) {
    CHECK(c["footprint"][k][0].get<double>() == Approx(E + want[k][0]).margin(1e-6));
    CHECK(c["footprint"][k][1].get<double>() == Approx(N + want[k][1]).margin(1e-6));
  }
  REQUIRE(d["rejected"].size() == 1);
  const Json& r = d["rejected"][0];
  CHECK(r["candidate"] == "c0003");
  CHECK(r["reason"] == "too_sparse");
  CHECK_THAT(r["detail"].get<std::string>(), Catch::Contains("below the 4 points/m²"));
  CHECK(r["density"] == 2.1);
  CHECK(r["density_needed"] == Json{{"class", 4.0}, {"model", 370.0}});
  CHECK(r["model_chain"] == "failed");
  CHECK(r["confidence"].is_null());  // too_sparse: classify decided nothing
  // Where the rejected candidate was (its frame's origin in the tile): score judges the none.
  CHECK(r["position"]["x"].get<double>() == Approx(E + 20));
  CHECK(r["position"]["y"].get<double>() == Approx(N + 20));
  const Json g = read_json(dir / "d.geojson");
  REQUIRE(g["features"].size() == 2);
  CHECK(g["features"][1]["properties"]["level"] == "class");
  CHECK(g["features"][1]["properties"]["class"] == "hatchback");
  CHECK(g["features"][1]["properties"]["model"].is_null());

  // A failed model chain with a class answer: the class answer stands.
  write(cands / "c0002" / "verdict.json", "");
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  CHECK(read_json(dir / "d.json")["detections"][1]["level"] == "class");
  // No verdict.json at all (a class-level candidate of the plan): the same.
  fs::remove(cands / "c0002" / "verdict.json");
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  CHECK(read_json(dir / "d.json")["detections"][1]["candidate"] == "c0002");
  // --class-name "": classify's answers are not read (v1 behaviour: c0002 none, c0003 failed).
  write(cands / "c0002" / "verdict.json",
        verdict((cands / "c0002" / "samples.pcd").string(), nullptr, 0.7, nullptr, nullptr).dump());
  REQUIRE(test::sh(cmd + " --class-name ''", dir / "err.txt", &err) == 0);
  const Json v1 = read_json(dir / "d.json");
  CHECK(v1["found"] == 1);
  CHECK(v1["by_reason"] == Json{{"failed", 1}, {"none", 1}});
  CHECK(v1["failed"] == 1);
  CHECK(v1["rejected"][1]["detail"] == "a stage of the model chain failed (see the candidate's .log files)");
}

TEST_CASE(
    "collect --contradicted-below: a doubtful model answer whose class classify contradicts gives way") {
  const fs::path dir = tile("contradicted");
  const fs::path cands = dir / "cands";
  // c0001: verify's model answer is a van at confidence 0.3; classify says a car (an suv).
  auto model_answer = [&](double confidence) {
    Json v = verdict((cands / "c0001" / "samples.pcd").string(), "van__bus", confidence, flat(0, 0, 0, 0),
                     flat(30, E + 10.25, N + 10.125, 100.5));
    v["class"] = "van";  // verify's class fields (a modelbase with classes)
    v["nearest_instance"] = "van__bus";
    v["class_score"] = 0.5;
    v["class_margin"] = 0.1;
    write(cands / "c0001" / "verdict.json", v.dump());
  };
  auto class_said = [&](const char* cls, const char* group, const char* reason) {
    write(cands / "c0001" / "class.json",
          class_answer(cands, "c0001", cls, group, reason, 900, reason ? Json() : flat(0, 0, 0, 0)).dump());
  };
  const std::string cmd = bin() + " -i " + (cands / "index.json").string() + " -o " +
                          (dir / "d.json").string() + " --class-name class.json";
  std::string err;
  auto first = [&](const std::string& options) {
    REQUIRE(test::sh(cmd + options, dir / "err.txt", &err) == 0);
    const Json d = read_json(dir / "d.json");
    for (const auto& x : d["detections"]) {
      if (x["candidate"] == "c0001")
        return x["level"].get<std::string>() + " " + x["class"].get<std::string>();
    }
    return std::string("none");
  };
  model_answer(0.3);
  class_said("suv", "car", nullptr);
  CHECK(first("") == "class suv");                            // the default, 0.5
  CHECK(first(" --contradicted-below 0") == "model van");     // off: the model answer first
  CHECK(first(" --contradicted-below 0.25") == "model van");  // 0.3 is not below 0.25
  model_answer(0.6);
  CHECK(first("") == "model van");  // confident enough
  model_answer(0.3);
  class_said("box-van", "van", nullptr);
  CHECK(first("") == "model van");  // classify's group agrees: no contradiction
  class_said("van", nullptr, nullptr);
  CHECK(first("") == "model van");  // its class agrees
  class_said(nullptr, nullptr, "vegetation_like");
  CHECK(first("") == "model van");  // classify named no class: nothing contradicts
  // A model without a class (the thesis modelbase has no classes): nothing to contradict.
  write(cands / "c0001" / "verdict.json", verdict((cands / "c0001" / "samples.pcd").string(), "sedan", 0.1,
                                                  flat(0, 0, 0, 0), flat(30, E + 10.25, N + 10.125, 100.5))
                                              .dump());
  class_said("box-van", "van", nullptr);
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  CHECK(read_json(dir / "d.json")["detections"][0]["model"] == "sedan");
  CHECK(test::sh(cmd + " --contradicted-below 1.5", dir / "err.txt", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--contradicted-below must be in [0, 1]"));
}

TEST_CASE(
    "collect --contradiction-level: a class answer contradicts a doubtful model answer only from another "
    "group") {
  const fs::path dir = tile("contradiction_level");
  const fs::path cands = dir / "cands";
  // c0001: verify's model answer of a class at confidence 0.3 (below --contradicted-below 0.5).
  auto model_answer = [&](const char* model, const char* cls) {
    Json v = verdict((cands / "c0001" / "samples.pcd").string(), model, 0.3, flat(0, 0, 0, 0),
                     flat(30, E + 10.25, N + 10.125, 100.5));
    v["class"] = cls;
    v["nearest_instance"] = model;
    v["class_score"] = 0.5;
    v["class_margin"] = 0.1;
    write(cands / "c0001" / "verdict.json", v.dump());
  };
  // classify's class answer (group nullptr: a class.json without one).
  auto class_said = [&](const char* cls, const char* group) {
    write(cands / "c0001" / "class.json",
          class_answer(cands, "c0001", cls, group, nullptr, 900, flat(0, 0, 0, 0)).dump());
  };
  const std::string cmd = bin() + " -i " + (cands / "index.json").string() + " -o " +
                          (dir / "d.json").string() + " --class-name class.json";
  std::string err;
  auto first = [&](const std::string& options) {
    REQUIRE(test::sh(cmd + options, dir / "err.txt", &err) == 0);
    const Json d = read_json(dir / "d.json");
    for (const auto& x : d["detections"]) {
      if (x["candidate"] == "c0001")
        return x["level"].get<std::string>() + " " + x["class"].get<std::string>();
    }
    return std::string("none");
  };
  // The unseen Ford Ranger's case (open-set.md, twelfth round): verify names the modelbase's
  // pickup, classify the car entries' envelope. A pickup is of classify's car group: its answer
  // does not exclude the pickup, and the model answer stands; the sixth round's rule (class) set
  // it aside.
  model_answer("pickup__gz_pickup", "pickup");
  class_said("car", "car");
  CHECK(first("") == "model pickup");
  CHECK(first(" --contradiction-level group") == "model pickup");
  CHECK(first(" --contradiction-level class") == "class car");
  CHECK(first(" --contradicted-below 0 --contradiction-level class") == "model pickup");  // off
  class_said("suv", nullptr);  // no group in the class.json: its class's group (car)
  CHECK(first("") == "model pickup");
  CHECK(first(" --contradiction-level class") == "class suv");
  // Another group still contradicts: a van, a bus, a tracked APC, a class of a group of its own.
  class_said("van", "van");
  CHECK(first("") == "class van");
  class_said("bus", "bus");
  CHECK(first("") == "class bus");
  class_said("tracked-apc", "tracked");
  CHECK(first("") == "class tracked-apc");
  class_said("tractor", "tractor");
  CHECK(first("") == "class tractor");
  // The sixth round's own cases are kept: a van model against a car answer gives way at either level.
  model_answer("van__ch_uaz_bus", "van");
  class_said("car", "car");
  CHECK(first("") == "class car");
  CHECK(first(" --contradiction-level class") == "class car");
  class_said("suv", "car");
  CHECK(first("") == "class suv");
  // A tracked APC model answer stands against classify's tank (both tracked), not against a car.
  model_answer("tracked-apc__ch_m113", "tracked-apc");
  class_said("tank", "tracked");
  CHECK(first("") == "model tracked-apc");
  CHECK(first(" --contradiction-level class") == "class tank");
  class_said("car", "car");
  CHECK(first("") == "class car");
  // A model class that is a group's name (the modelbase's "truck") agrees with its members at
  // either level; a class of its own agrees only with itself.
  model_answer("truck__ch_man_5t", "truck");
  class_said("box-truck", "truck");
  CHECK(first("") == "model truck");
  CHECK(first(" --contradiction-level class") == "model truck");
  model_answer("tractor__oat_tractor", "tractor");
  class_said("wheel-loader", "machine");
  CHECK(first("") == "class wheel-loader");
  // A confident model answer is never contradicted, whatever the level.
  Json v = read_json(cands / "c0001" / "verdict.json");
  v["confidence"] = 0.7;
  write(cands / "c0001" / "verdict.json", v.dump());
  CHECK(first("") == "model tractor");
  CHECK(test::sh(cmd + " --contradiction-level family", dir / "err.txt", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--contradiction-level must be group or class, not \"family\""));
}

TEST_CASE(
    "collect --model-classes: a model answer without a class is written with its model's class and group; "
    "no decision changes") {
  const fs::path dir = tile("model_classes");
  const fs::path cands = dir / "cands";
  // The tile: c0001 verify's sedan (0.9), c0002 none, c0003 verify's tank (0.8), neither
  // verdict with a class (the thesis modelbase has no <model>.class files).
  const fs::path csv = dir / "classes.csv";
  write(csv, "model,class\n# the test's models\nsedan,sedan\nvan__bus,van\n");  // no tank
  const std::string cmd = bin() + " -i " + (cands / "index.json").string() + " -o " +
                          (dir / "d.json").string() + " --geojson " + (dir / "d.geojson").string();
  std::string err;
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  const Json plain = read_json(dir / "d.json");
  REQUIRE(plain["detections"].size() == 2);
  CHECK_FALSE(plain["detections"][0].contains("class"));  // without the option: as before
  CHECK_FALSE(plain["detections"][0].contains("group"));
  REQUIRE(test::sh(cmd + " --model-classes " + csv.string(), dir / "err.txt", &err) == 0);
  const Json d = read_json(dir / "d.json");
  REQUIRE(d["detections"].size() == 2);
  CHECK(d["detections"][0]["model"] == "sedan");
  CHECK(d["detections"][0]["class"] == "sedan");
  CHECK(d["detections"][0]["group"] == "car");  // the taxonomy's group of sedan
  CHECK(d["detections"][1]["model"] == "tank");
  CHECK_FALSE(d["detections"][1].contains("class"));  // tank is not in the file: none
  CHECK_FALSE(d["detections"][1].contains("group"));
  const Json g = read_json(dir / "d.geojson");
  CHECK(g["features"][0]["properties"]["class"] == "sedan");
  CHECK(g["features"][0]["properties"]["group"] == "car");
  CHECK(d["provenance"]["inputs"].back() == csv.string());
  CHECK(d["provenance"]["parameters"]["model-classes"] == csv.string());
  // Nothing else in the document changes.
  Json a = d, b = plain;
  for (Json* x : {&a, &b}) {
    x->erase("provenance");
    for (auto& det : (*x)["detections"]) {
      det.erase("class");
      det.erase("group");
    }
  }
  CHECK(a == b);
  // The shipped file: the thesis models' classes (tank a tank, of the tracked group).
  const std::string shipped = std::string(CANOPY_SOURCE_DIR) + "/share/models/classes.csv";
  REQUIRE(test::sh(cmd + " --model-classes " + shipped, dir / "err.txt", &err) == 0);
  const Json s = read_json(dir / "d.json");
  CHECK(s["detections"][0]["class"] == "sedan");
  CHECK(s["detections"][1]["class"] == "tank");
  CHECK(s["detections"][1]["group"] == "tracked");
  // A verdict's own class stays, and gets its group (verify writes a class only), with or
  // without the option.
  Json own = verdict((cands / "c0003" / "samples.pcd").string(), "tank", 0.8, flat(180, 0.5, 0, 0), nullptr);
  own["class"] = "tracked-apc";
  own["nearest_instance"] = "tank";
  own["class_score"] = 0.5;
  own["class_margin"] = 0.1;
  write(cands / "c0003" / "verdict.json", own.dump());
  REQUIRE(test::sh(cmd + " --model-classes " + shipped, dir / "err.txt", &err) == 0);
  const Json o = read_json(dir / "d.json");
  CHECK(o["detections"][1]["class"] == "tracked-apc");
  CHECK(o["detections"][1]["group"] == "tracked");
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  const Json o2 = read_json(dir / "d.json");
  CHECK(o2["detections"][1]["class"] == "tracked-apc");
  CHECK(o2["detections"][1]["group"] == "tracked");
  CHECK_FALSE(o2["detections"][0].contains("group"));  // sedan: no class, so no group

  // The decision is unchanged: a doubtful sedan answer (0.1, no class) and classify's box van
  // (the van group). Without a class nothing contradicts the model answer (--contradicted-below
  // 0.5 by default); were the file's class given to it before the decision, the van answer would
  // win. With the option the model answer stands and only its class is written.
  write(cands / "c0001" / "verdict.json", verdict((cands / "c0001" / "samples.pcd").string(), "sedan", 0.1,
                                                  flat(0, 0, 0, 0), flat(30, E + 10.25, N + 10.125, 100.5))
                                              .dump());
  write(cands / "c0001" / "class.json",
        class_answer(cands, "c0001", "box-van", "van", nullptr, 900, flat(0, 0, 0, 0)).dump());
  auto c0001 = [&](const std::string& options) {
    REQUIRE(test::sh(cmd + options, dir / "err.txt", &err) == 0);
    const Json x = read_json(dir / "d.json");
    for (const auto& det : x["detections"]) {
      if (det["candidate"] == "c0001")
        return det["level"].get<std::string>() + " " + det.value("class", std::string("-")) + " " +
               det.value("group", std::string("-")) + " " + x["by_level"].dump();
    }
    return std::string("none");
  };
  CHECK(c0001("") == R"(model - - {"model":2,"class":0})");
  CHECK(c0001(" --model-classes " + csv.string()) == R"(model sedan car {"model":2,"class":0})");
  // With the class in the verdict itself the contradiction applies (the rule, unchanged).
  Json contradicted = read_json(cands / "c0001" / "verdict.json");
  contradicted["class"] = "sedan";
  contradicted["nearest_instance"] = "sedan";
  contradicted["class_score"] = 0.5;
  contradicted["class_margin"] = 0.1;
  write(cands / "c0001" / "verdict.json", contradicted.dump());
  CHECK(c0001(" --model-classes " + csv.string()) == R"(class box-van van {"model":1,"class":1})");
  // A refusal on the shape sets the doubtful answer aside with the option as without it.
  write(cands / "c0001" / "verdict.json", verdict((cands / "c0001" / "samples.pcd").string(), "sedan", 0.1,
                                                  flat(0, 0, 0, 0), flat(30, E + 10.25, N + 10.125, 100.5))
                                              .dump());
  Json refusal = class_answer(cands, "c0001", nullptr, nullptr, "not_vehicle_shape", 900, Json());
  refusal["refused_on"] = "shape";
  write(cands / "c0001" / "class.json", refusal.dump());
  CHECK(c0001("") == "none");
  CHECK(c0001(" --model-classes " + csv.string()) == "none");

  // A bad file: exit 1 naming it (and the line), nothing written; a missing one is named too.
  fs::remove(dir / "d.json");
  for (const auto& [text, message] : std::vector<std::pair<std::string, std::string>>{
           {"model,class\nsedan\n", "line 2: expected 'model,class', got 'sedan'"},
           {"model,class\nsedan,Sedan\n", "line 2: class 'Sedan' is not 1-64 characters of [a-z0-9-]"},
           {"sedan,sedan\n", "line 1: the first line must be the header 'model,class'"},
           {"model,class\nsedan,sedan\nsedan,car\n", "line 3: model 'sedan' given twice"}}) {
    write(csv, text);
    CHECK(test::sh(cmd + " --model-classes " + csv.string(), dir / "err.txt", &err) == 1);
    CHECK_THAT(err, Catch::Contains(csv.string() + ": " + message));
    CHECK_FALSE(fs::exists(dir / "d.json"));
  }
  CHECK(test::sh(cmd + " --model-classes " + (dir / "nope.csv").string(), dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains((dir / "nope.csv").string()));
  CHECK_FALSE(fs::exists(dir / "d.json"));
  // --plan reads no answers and so no classes (as --calibration): the bad file is not read.
  REQUIRE(test::sh(bin() + " -q -i " + (cands / "index.json").string() + " --plan " +
                       (dir / "cands.mk").string() + " --model-classes " + csv.string(),
                   dir / "err.txt", &err) == 0);
  CHECK_THAT(read_text(dir / "cands.mk"), Catch::Contains("TILE_CANDS"));
}

TEST_CASE("collect --refused-below: a doubtful model answer gives way to classify's refusal on the shape") {
  const fs::path dir = tile("refused");
  const fs::path cands = dir / "cands";
  // c0001: verify's model answer, a car (no class: the rule needs none) at a given confidence.
  auto model_answer = [&](double confidence) {
    write(cands / "c0001" / "verdict.json",
          verdict((cands / "c0001" / "samples.pcd").string(), "sedan", confidence, flat(0, 0, 0, 0),
                  flat(30, E + 10.25, N + 10.125, 100.5))
              .dump());
  };
  // classify's none for c0001 with a reason and what it rests on (nullptr: an older class.json).
  auto refused = [&](const char* reason, const char* on) {
    Json k = class_answer(cands, "c0001", nullptr, nullptr, reason, 900, Json());
    k["detail"] = "an oval outline";
    if (on) k["refused_on"] = on;
    write(cands / "c0001" / "class.json", k.dump());
  };
  const std::string cmd = bin() + " -i " + (cands / "index.json").string() + " -o " +
                          (dir / "d.json").string() + " --class-name class.json";
  std::string err;
  auto c0001 = [&](const std::string& options) {
    REQUIRE(test::sh(cmd + options, dir / "err.txt", &err) == 0);
    const Json d = read_json(dir / "d.json");
    for (const auto& x : d["detections"]) {
      if (x["candidate"] == "c0001") return "model " + x["model"].get<std::string>();
    }
    for (const auto& x : d["rejected"]) {
      if (x["candidate"] == "c0001")
        return x["reason"].get<std::string>() + " " + x["model_chain"].get<std::string>() + ": " +
               x["detail"].get<std::string>();
    }
    return std::string("missing");
  };
  model_answer(0.6);
  refused("not_vehicle_shape", "shape");
  CHECK(c0001(" --refused-below 0") == "model sedan");    // off: the model answer first
  CHECK(c0001(" --refused-below 0.5") == "model sedan");  // 0.6 is not below 0.5
  CHECK(c0001("") ==                                      // the default, 0.8
        "not_vehicle_shape set_aside: an oval outline; the model chain's sedan (confidence 0.60) set aside "
        "for it "
        "(collect --refused-below)");
  const Json d = read_json(dir / "d.json");
  CHECK(d["found"] == 1);  // c0003's tank stays
  CHECK(d["by_reason"]["not_vehicle_shape"] == 1);
  CHECK(d["rejected"][0]["confidence"] == 0.6);  // classify's confidence in its none
  refused("vegetation_like", "surface");
  CHECK(c0001(" --refused-below 0.8").rfind("vegetation_like set_aside: ", 0) == 0);  // the surface too
  // A none on the density or the size alone does not set a model answer aside, nor one that does
  // not say what it rests on (classify before refused_on).
  refused("not_vehicle_shape", "size");
  CHECK(c0001(" --refused-below 0.8") == "model sedan");
  refused("too_small", "size");
  CHECK(c0001(" --refused-below 0.8") == "model sedan");
  refused("too_sparse", "density");
  CHECK(c0001(" --refused-below 0.8") == "model sedan");
  refused("not_vehicle_shape", nullptr);
  CHECK(c0001(" --refused-below 0.8") == "model sedan");
  // A class answer is no refusal (--contradicted-below's matter).
  write(cands / "c0001" / "class.json",
        class_answer(cands, "c0001", "hatchback", "car", nullptr, 900, flat(0, 0, 0, 0)).dump());
  CHECK(c0001(" --refused-below 0.8") == "model sedan");
  // The model's confidence 1 is never below; the range is [0, 1]; a bad refused_on is named.
  model_answer(1.0);
  refused("not_vehicle_shape", "shape");
  CHECK(c0001(" --refused-below 1") == "model sedan");
  model_answer(0.99);
  CHECK(c0001(" --refused-below 1").rfind("not_vehicle_shape set_aside", 0) == 0);
  CHECK(test::sh(cmd + " --refused-below 1.5", dir / "err.txt", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--refused-below must be in [0, 1]"));
  refused("not_vehicle_shape", "roundness");
  CHECK(test::sh(cmd + " --refused-below 0.8", dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("class.json"));
  CHECK_THAT(err, Catch::Contains("refused_on must be density, surface, size, shape or null"));
}

TEST_CASE(
    "collect v2: most candidates too sparse and no model chain: the warning says why and what would help") {
  const fs::path dir = tile("sparse_warning");
  const fs::path cands = dir / "cands";
  // detect's density for the tile, and every candidate classified only (no verdict.json).
  Json index = read_json(cands / "index.json");
  index["density"] = Json{{"all", 31.0}, {"ground", 28.0}, {"first", nullptr}};
  write(cands / "index.json", index.dump());
  for (const char* id : {"c0001", "c0002", "c0003"}) fs::remove(cands / id / "verdict.json");
  write(cands / "c0001" / "class.json",
        class_answer(cands, "c0001", nullptr, nullptr, "too_sparse", 2.5, nullptr).dump());
  write(cands / "c0002" / "class.json",
        class_answer(cands, "c0002", nullptr, nullptr, "too_sparse", 3.5, nullptr).dump());
  write(cands / "c0003" / "class.json",
        class_answer(cands, "c0003", nullptr, nullptr, "vegetation_like", 20, nullptr).dump());
  std::string err;
  REQUIRE(test::sh(bin() + " -i " + (cands / "index.json").string() + " -o " + (dir / "d.json").string(),
                   dir / "err.txt", &err) == 0);
  const Json d = read_json(dir / "d.json");
  CHECK(d["found"] == 0);
  CHECK(d["by_reason"] == Json{{"too_sparse", 2}, {"vegetation_like", 1}});
  CHECK(d["density"]["ground"] == 28.0);
  const std::string w = d["warning"];
  CHECK_THAT(w,
             Catch::Contains("2 of 3 candidates rejected as too_sparse (median object density 3 points/m², "
                             "class level needs 4, model level 370)"));
  // Most candidates are too sparse even for a class: "at most", not the promise "only".
  CHECK_THAT(w, Catch::Contains(
                    "open-ground density 28 points/m²: below the 370 points/m² that model-level recognition "
                    "needs; class-level answers at most"));
  CHECK_THAT(w, Catch::EndsWith("see docs/decisions/classify.md"));
  CHECK_THAT(err, Catch::Contains("collect: warning: 2 of 3 candidates rejected as too_sparse"));
  // Neither a verdict nor a class answer: named, nothing written.
  fs::remove(cands / "c0003" / "class.json");
  fs::remove(dir / "d.json");
  CHECK(test::sh(bin() + " -q -i " + (cands / "index.json").string() + " -o " + (dir / "d.json").string(),
                 dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("c0003/verdict.json"));
  CHECK_FALSE(test::exists(dir / "d.json"));
  // A tile dense enough whose model chain did not run (no verdict anywhere): said so, not blamed
  // on the density (it had read "tile density 900 points/m²: below the 370 ...").
  index["density"] = Json{{"all", 950.0}, {"ground", 900.0}};
  write(cands / "index.json", index.dump());
  write(cands / "c0003" / "class.json",
        class_answer(cands, "c0003", nullptr, nullptr, "vegetation_like", 20, nullptr).dump());
  REQUIRE(test::sh(bin() + " -i " + (cands / "index.json").string() + " -o " + (dir / "d.json").string(),
                   dir / "err.txt", &err) == 0);
  const std::string dense = read_json(dir / "d.json")["warning"];
  CHECK_THAT(dense, Catch::Contains(
                        "open-ground density 900 points/m²: dense enough for model-level recognition, but "
                        "no candidate has a model-chain verdict"));
  CHECK_THAT(dense, !Catch::Contains("below the 370"));
  // An index without the open ground's density: all returns', said so.
  index["density"] = Json{{"all", 31.0}, {"ground", nullptr}};
  write(cands / "index.json", index.dump());
  REQUIRE(test::sh(bin() + " -i " + (cands / "index.json").string() + " -o " + (dir / "d.json").string(),
                   dir / "err.txt", &err) == 0);
  CHECK_THAT(read_json(dir / "d.json")["warning"].get<std::string>(),
             Catch::Contains("tile density 31 points/m² (all returns): below the 370 points/m²"));
}

TEST_CASE("collect --plan: each candidate's level from its object density") {
  const fs::path dir = tile("plan_levels");
  Json index = read_json(dir / "cands" / "index.json");
  index["candidates"][0]["density"] = 900.0;          // dense: model
  index["candidates"][1]["object_points"] = 60;       // 60 / (3 x 2) = 10: class
  write(dir / "cands" / "index.json", index.dump());  // c0003: unknown: model
  std::string err;
  const std::string cmd =
      bin() + " -q -i " + (dir / "cands" / "index.json").string() + " --plan " + (dir / "cands.mk").string();
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  std::string mk = read_text(dir / "cands.mk");
  CHECK_THAT(mk, Catch::Contains(
                     "\nTILE_LEVEL_c0001 := model\nTILE_LEVEL_c0002 := class\nTILE_LEVEL_c0003 := model\n"));
  REQUIRE(test::sh(cmd + " --model-density 1000", dir / "err.txt", &err) == 0);
  CHECK_THAT(read_text(dir / "cands.mk"), Catch::Contains("\nTILE_LEVEL_c0001 := class\n"));
  REQUIRE(test::sh(cmd + " --model-density 5", dir / "err.txt", &err) == 0);
  CHECK_THAT(read_text(dir / "cands.mk"), Catch::Contains("\nTILE_LEVEL_c0002 := model\n"));
  CHECK(test::sh(cmd + " --model-density -1", dir / "err.txt", &err) == 2);
}

TEST_CASE("collect --size-only: the measured size picks the nearest model; no verdict, no class decision") {
  const fs::path dir = tile("size-only");
  const fs::path cands = dir / "cands";
  const fs::path mb = dir / "mb";
  // Two surfaces (label-1 box corners): "small" 4.5 x 1.8 x 1.45 m with its origin at the rear
  // (x in [0, 4.5]); "long" 12 x 2.2 x 3.4 m lying along y (x in [-1.1, 1.1], y in [-6, 6]).
  auto surface = [](double x0, double x1, double y0, double y1, double z1) {
    std::string pts;
    for (double x : {x0, x1})
      for (double y : {y0, y1})
        for (double z : {0.2, z1})
          pts += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + " 1\n";
    return "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z label\nSIZE 8 8 8 4\nTYPE F F F I\nCOUNT 1 1 1 1\nWIDTH "
           "8\n"
           "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 8\nDATA ascii\n" +
           pts;
  };
  write(mb / "small.pcd", surface(0, 4.5, -0.9, 0.9, 1.45));
  write(mb / "long.pcd", surface(-1.1, 1.1, -6, 6, 3.4));
  // An interrupted writer's temporary copy of "small" (hidden): not a model; it would win the
  // tie with "small" by name.
  write(mb / ".small.tmp77-1.pcd", surface(0, 4.5, -0.9, 0.9, 1.45));
  auto measured = [](Json j, double l, double w, double h, double cx, double cy, double heading,
                     double edge = 0) {
    j["measured"] = Json{{"size", {l, w, h}},
                         {"centre", {cx, cy}},
                         {"heading_deg", heading},
                         {"spacing", 0.1},
                         {"edge_correction", edge}};
    return j;
  };
  // c0001: verify said sedan; classify a box truck measured 11.7 x 2.2 x 3.3 with an edge
  // correction of 0.1 m (the object 11.8 x 2.3 x 3.3) at the candidate's origin (tile E + 10,
  // N + 10, heading 0). c0002: a hatchback measured 4.5 x 1.8 x 1.45 at
  // (1, 0.5), heading 90 (tile E + 6, N + 25.5). c0003: verify said tank; classify called it
  // vegetation, measured 4.4 x 1.9 x 1.5 at its origin (tile E + 20, N + 20, heading 90).
  write(cands / "c0001" / "class.json",
        measured(class_answer(cands, "c0001", "box-truck", "truck", nullptr, 900, flat(0, 0, 0, 0)), 11.7,
                 2.2, 3.3, 0, 0, 0, 0.1)
            .dump());
  write(cands / "c0002" / "class.json",
        measured(class_answer(cands, "c0002", "hatchback", "car", nullptr, 30, flat(90, 1, 0.5, 0)), 4.5, 1.8,
                 1.45, 1, 0.5, 90)
            .dump());
  write(cands / "c0003" / "class.json",
        measured(class_answer(cands, "c0003", nullptr, nullptr, "vegetation_like", 50, nullptr), 4.4, 1.9,
                 1.5, 0, 0, 0)
            .dump());
  std::string err;
  const std::string cmd =
      bin() + " -i " + (cands / "index.json").string() + " -o " + (dir / "d.json").string() + " --size-only";
  CHECK(test::sh(cmd, dir / "err.txt", &err) == 2);  // needs --modelbase
  CHECK_THAT(err, Catch::Contains("--size-only needs --modelbase"));
  CHECK(test::sh(cmd + " --modelbase " + mb.string() + " --size-gate 0", dir / "err.txt", &err) == 2);
  REQUIRE(test::sh(cmd + " --modelbase " + mb.string(), dir / "err.txt", &err) == 0);
  const Json d = read_json(dir / "d.json");
  CHECK(d["found"] == 3);
  CHECK(d["by_level"] == Json{{"model", 3}, {"class", 0}});
  CHECK(d["warning"].is_null());  // no verdict read on purpose: no "model chain did not run" warning
  REQUIRE(d["detections"].size() == 3);
  // c0001: "long" (differences 1.7%, 4.5%, 2.9%: confidence 1 - 0.045 / 0.25), turned a quarter
  // so its 12 m side lies along the measured length: heading -90, its centre (the origin) on
  // the rectangle's.
  const Json& a = d["detections"][0];
  CHECK(a["model"] == "long");
  CHECK(a["level"] == "model");
  CHECK(a["confidence"].get<double>() == Approx(1 - (2.3 - 2.2) / 2.2 / 0.25));
  CHECK(a["pose"]["x"].get<double>() == Approx(E + 10).margin(1e-6));
  CHECK(a["pose"]["y"].get<double>() == Approx(N + 10).margin(1e-6));
  CHECK(std::fmod(a["pose"]["heading"].get<double>() + 360, 360) == Approx(270));
  CHECK(a["footprint_from"] == "model");
  CHECK_FALSE(a.contains("class"));  // none of classify's decisions: the model alone
  // c0002: "small" exactly (confidence 1), its box centre (2.25 m ahead of its origin) on the
  // rectangle's centre, so the origin lies 2.25 m behind it along heading 90: (E + 6, N + 23.25).
  const Json& b = d["detections"][1];
  CHECK(b["model"] == "small");
  CHECK(b["confidence"].get<double>() == Approx(1));
  CHECK(b["pose"]["x"].get<double>() == Approx(E + 6).margin(1e-6));
  CHECK(b["pose"]["y"].get<double>() == Approx(N + 23.25).margin(1e-6));
  CHECK(b["pose"]["heading"].get<double>() == Approx(90));
  // c0003: classify's "vegetation" does not count, its size does: "small", turned with the
  // candidate frame (heading 90), origin 2.25 m behind the rectangle's centre (E + 20, N + 20).
  const Json& c = d["detections"][2];
  CHECK(c["model"] == "small");
  CHECK(c["pose"]["x"].get<double>() == Approx(E + 20).margin(1e-6));
  CHECK(c["pose"]["y"].get<double>() == Approx(N + 17.75).margin(1e-6));
  // No verify verdict read: the tank and the sedan are nobody's answer.
  const std::string inputs = d["provenance"]["inputs"].dump();
  CHECK(inputs.find("verdict.json") == std::string::npos);
  CHECK(inputs.find("long.pcd") != std::string::npos);
  // --model-classes: a size-only answer names a model, so it is written with the file's class of
  // that model (and its group) like verify's class-less answers; a model not listed stays without.
  write(dir / "classes.csv", "model,class\nsmall,hatchback\n");
  REQUIRE(test::sh(cmd + " --modelbase " + mb.string() + " --model-classes " + (dir / "classes.csv").string(),
                   dir / "err.txt", &err) == 0);
  const Json mc = read_json(dir / "d.json");
  REQUIRE(mc["detections"].size() == 3);
  CHECK_FALSE(mc["detections"][0].contains("class"));  // long
  CHECK(mc["detections"][1]["class"] == "hatchback");  // small
  CHECK(mc["detections"][1]["group"] == "car");
  CHECK(mc["detections"][2]["class"] == "hatchback");
  CHECK(mc["detections"][1]["confidence"] == d["detections"][1]["confidence"]);
  // A tighter gate: only c0002's exact size passes; the others are rejected with classify's
  // reason (c0001: it answered a class, so "none").
  REQUIRE(test::sh(cmd + " --modelbase " + mb.string() + " --size-gate 0.02", dir / "err.txt", &err) == 0);
  const Json t = read_json(dir / "d.json");
  REQUIRE(t["detections"].size() == 1);
  CHECK(t["detections"][0]["candidate"] == "c0002");
  CHECK(t["by_reason"] == Json{{"none", 1}, {"vegetation_like", 1}});
  // The pure functions: nearest in (L, W, H), ties to the first name; the largest relative
  // difference.
  std::map<std::string, collect::ModelBox> boxes{{"a", {0, 4, -1, 1, 1.5}}, {"b", {-1, 1, -2, 2, 1.5}}};
  CHECK(collect::nearest_by_size({4, 2, 1.5}, boxes) == "a");  // both 4 x 2 x 1.5: the first
  CHECK(collect::nearest_by_size({9, 3, 3}, {}) == "");
  CHECK(collect::size_difference({5, 2, 1.5}, boxes.at("a")) == Approx(0.25));
}

TEST_CASE("collect --plan: the density rule's options for the model-level candidates below 370 points/m²") {
  const fs::path dir = tile("plan_scale");
  Json index = read_json(dir / "cands" / "index.json");
  index["candidates"][0]["density"] = 900.0;          // dense end: no options, today's stages
  index["candidates"][1]["density"] = 200.0;          // scaled: voxel 175 mm (density_scale.h)
  write(dir / "cands" / "index.json", index.dump());  // c0003: unknown density: no options
  std::string err;
  const std::string cmd =
      bin() + " -q -i " + (dir / "cands" / "index.json").string() + " --plan " + (dir / "cands.mk").string();
  REQUIRE(test::sh(cmd + " --model-density 150", dir / "err.txt", &err) == 0);
  std::string mk = read_text(dir / "cands.mk");
  CHECK_THAT(mk, Catch::Contains(
                     "\nTILE_LEVEL_c0001 := model\nTILE_LEVEL_c0002 := model\nTILE_LEVEL_c0003 := model\n"
                     "TILE_FITVOX_c0002 := --voxel 175mm\n"
                     "TILE_COCONE_c0002 := --max-area 0.0747681\n"
                     "TILE_NCUT_c0002 := --radius 700mm --dense-radius 239mm\n"));
  CHECK_THAT(mk, !Catch::Contains("VERIFY"));
  CHECK_THAT(mk, !Catch::Contains("_c0001 := --"));
  CHECK_THAT(mk, !Catch::Contains("_c0003 := --"));
  // The dense end alone: the plan before the rule, byte for byte.
  index["candidates"][1]["density"] = 400.0;
  write(dir / "cands" / "index.json", index.dump());
  REQUIRE(test::sh(cmd + " --model-density 150", dir / "err.txt", &err) == 0);
  const std::string dense = read_text(dir / "cands.mk");
  CHECK_THAT(dense, !Catch::Contains("FITVOX"));
  // A class-level candidate (below --model-density) runs no model chain: no options.
  index["candidates"][1]["density"] = 100.0;
  write(dir / "cands" / "index.json", index.dump());
  REQUIRE(test::sh(cmd + " --model-density 150", dir / "err.txt", &err) == 0);
  mk = read_text(dir / "cands.mk");
  CHECK_THAT(mk, Catch::Contains("\nTILE_LEVEL_c0002 := class\n"));
  CHECK_THAT(mk, !Catch::Contains("FITVOX"));
  // --no-density-scale: model level at 100 points/m², with the files' lengths.
  REQUIRE(test::sh(cmd + " --model-density 50 --no-density-scale", dir / "err.txt", &err) == 0);
  mk = read_text(dir / "cands.mk");
  CHECK_THAT(mk, Catch::Contains("\nTILE_LEVEL_c0002 := model\n"));
  CHECK_THAT(mk, !Catch::Contains("FITVOX"));
  REQUIRE(test::sh(cmd + " --model-density 50", dir / "err.txt", &err) == 0);
  CHECK_THAT(read_text(dir / "cands.mk"), Catch::Contains("TILE_FITVOX_c0002 := --voxel 247mm\n"));
}

namespace {

// A verdict of collect's own (collect::Verdict) for candidate `id`: a model, a class or none.
collect::Verdict answer(const std::string& id, const std::string& level, const std::string& model,
                        const std::string& cls, double confidence, const std::string& reason = "") {
  collect::Verdict v;
  v.name = id + "/" + (level == "class" ? "class.json" : "verdict.json");
  v.candidate = id + "/samples.pcd";
  v.level = level;
  v.model = model;
  v.cls = cls;
  v.confidence = confidence;
  v.reason = reason;
  if (!model.empty() || !cls.empty())
    v.pose_tile = collect::Matrix{1, 0, 0, E, 0, 1, 0, N, 0, 0, 1, 0, 0, 0, 0, 1};
  return v;
}

// The detections document without its confidences: what the calibration must not change.
Json without_confidences(Json d) {
  for (auto* list : {&d["detections"], &d["rejected"]}) {
    for (auto& x : *list) x.erase("confidence");
  }
  return d;
}

const char* const kCalibrationIni =
    "; a test calibration\n"
    "model-bias = 1\nmodel-slope = 2\n"
    "class-bias = 2   # comment\nclass-slope = 1\n"
    "none-bias = -0.5\nnone-slope = 0.5\n"
    "\n"
    "none-class-bias = 0.3\nnone-class-slope = 1.5\n"
    "none-dense-bias = 1\nnone-dense-slope = 1.2\n"
    "none-coarse-bias = -1\nnone-coarse-slope = 0.8\n";

}  // namespace

TEST_CASE(
    "collect --calibration: each level's stated confidence through its own Platt map, answers unchanged") {
  // p' = logistic(bias + slope ln(p / (1 - p))), by hand: model (1, 2) at 0.9: logistic(1 + 2 ln 9) =
  // 0.99547881; none (-0.5, 0.5) at 0.6: 0.42622561; none-dense (1, 1.2) at 0.6: logistic(1 + 1.2 ln 1.5)
  // = 0.81556110; none-class (0.3, 1.5) at 0.25: 0.20621089;
  // class (2, 1) at 0.7: 0.94517884.
  const collect::Calibration cal = collect::parse_calibration(kCalibrationIni, "cal.ini");
  CHECK(cal.name == "cal.ini");
  CHECK(cal.model.bias == 1);
  CHECK(cal.model.slope == 2);
  CHECK(cal.none_class.slope == 1.5);
  {  // The same file with a UTF-8 BOM and CRLF line ends reads the same (formats/ini.h).
    std::string crlf = "\xEF\xBB\xBF";
    for (const char* c = kCalibrationIni; *c; ++c)
      crlf += *c == '\n' ? std::string("\r\n") : std::string(1, *c);
    const collect::Calibration dos = collect::parse_calibration(crlf, "cal.ini");
    CHECK(dos.model.slope == 2);
    CHECK(dos.cls.bias == 2);
    CHECK(dos.none.bias == -0.5);
    CHECK(dos.none_class.bias == 0.3);
  }
  CHECK(collect::calibrated(cal.model, 0.9) == Approx(0.99547881).epsilon(1e-7));
  CHECK(collect::calibrated(cal.none, 0.6) == Approx(0.42622561).epsilon(1e-7));
  CHECK(collect::calibrated(cal.none_dense, 0.6) == Approx(0.81556110).epsilon(1e-7));
  CHECK(collect::calibrated(cal.none_class, 0.25) == Approx(0.20621089).epsilon(1e-7));
  CHECK(collect::calibrated(cal.cls, 0.7) == Approx(0.94517884).epsilon(1e-7));
  CHECK(collect::calibrated(collect::PlattMap{}, 0.123) == 0.123);  // the identity is exact
  CHECK(collect::calibrated(cal.none, 1.0) < 1.0);  // p clamped: finite, below 1 where the map says so
  CHECK(collect::calibrated(cal.none, 0.0) > 0.0);

  collect::Inputs in;
  in.index.name = "idx.json";
  for (const char* id : {"c1", "c2", "c3", "c4"}) {
    collect::Candidate c;
    c.id = id;
    c.transform = {1, 0, 0, E, 0, 1, 0, N, 0, 0, 1, 0, 0, 0, 0, 1};
    in.index.candidates.push_back(c);
  }
  in.provenance = {"collect", "9.9", {}, {"idx.json"}};
  in.answers = {
      // c1: verify's model answer (classify's class beside it is not the answer).
      {answer("c1", "", "sedan", "car", 0.9), answer("c1", "class", "", "car", 0.4)},
      // c2: both levels said none: verify's none confidence through the none-dense map (its density
      // is unknown: not one of the density rule's coarse candidates).
      {answer("c2", "", "", "", 0.6), answer("c2", "class", "", "", 0.999, "not_vehicle_shape")},
      // c3: the model chain did not run; classify's none through the none-class map.
      {collect::absent_verdict("c3/verdict.json"), answer("c3", "class", "", "", 0.25, "not_vehicle_shape")},
      // c4: the model chain said none, classify a class: the class map.
      {answer("c4", "", "", "", 0.3), answer("c4", "class", "", "hatchback", 0.7)}};
  collect::Params p;
  const Json before = Json::parse(collect::run(p, in).detections);
  p.calibration = cal;
  const Json after = Json::parse(collect::run(p, in).detections);
  REQUIRE(after["detections"].size() == 2);
  REQUIRE(after["rejected"].size() == 2);
  CHECK(after["detections"][0]["candidate"] == "c1");
  CHECK(after["detections"][0]["confidence"].get<double>() == Approx(0.99547881).epsilon(1e-7));
  CHECK(after["detections"][1]["candidate"] == "c4");
  CHECK(after["detections"][1]["confidence"].get<double>() == Approx(0.94517884).epsilon(1e-7));
  CHECK(after["rejected"][0]["candidate"] == "c2");
  CHECK(after["rejected"][0]["confidence"].get<double>() == Approx(0.81556110).epsilon(1e-7));
  CHECK(after["rejected"][1]["candidate"] == "c3");
  CHECK(after["rejected"][1]["confidence"].get<double>() == Approx(0.20621089).epsilon(1e-7));
  // Without a calibration (the ablation): each level's own confidence, as before.
  CHECK(before["detections"][0]["confidence"] == 0.9);
  CHECK(before["detections"][1]["confidence"] == 0.7);
  CHECK(before["rejected"][0]["confidence"] == 0.6);
  CHECK(before["rejected"][1]["confidence"] == 0.25);
  // Only the confidences differ: the same answers, levels, poses, reasons.
  CHECK(without_confidences(before) == without_confidences(after));
  // A doubtful model answer that gives way to a contradicting class (--contradicted-below) is
  // decided on verify's own confidence, then states the class map's.
  in.answers = {{answer("c1", "", "sedan", "car", 0.45), answer("c1", "class", "", "truck", 0.7)}};
  in.index.candidates.resize(1);
  const Json way = Json::parse(collect::run(p, in).detections);
  CHECK(way["detections"][0]["class"] == "truck");
  CHECK(way["detections"][0]["confidence"].get<double>() == Approx(0.94517884).epsilon(1e-7));
}

TEST_CASE("collect --calibration: the file on the command line; a bad one is named, nothing is written") {
  const fs::path dir = tile("calibration");
  const fs::path cands = dir / "cands";
  const fs::path ini = dir / "cal.ini";
  write(ini, kCalibrationIni);
  std::string err;
  const std::string cmd = bin() + " -i " + (cands / "index.json").string() + " -o " + (dir / "d.json").string();
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  const Json plain = read_json(dir / "d.json");
  CHECK(plain["detections"][0]["confidence"] == 0.9);  // no --calibration: as verify stated it
  REQUIRE(test::sh(cmd + " --calibration " + ini.string(), dir / "err.txt", &err) == 0);
  const Json d = read_json(dir / "d.json");
  CHECK(d["detections"][0]["confidence"].get<double>() == Approx(0.99547881).epsilon(1e-7));  // sedan 0.9
  CHECK(d["rejected"][0]["confidence"].get<double>() ==
        Approx(1 / (1 + std::exp(-1 - 1.2 * std::log(0.7 / 0.3)))).epsilon(1e-9));  // none-dense 0.7
  CHECK(d["provenance"]["inputs"].back() == ini.string());
  CHECK(without_confidences(d)["detections"] == without_confidences(plain)["detections"]);
  // The shipped calibration parses.
  REQUIRE(test::sh(cmd + " --calibration " + std::string(CANOPY_SOURCE_DIR) + "/share/params/calibration.ini",
                   dir / "err.txt", &err) == 0);
  // Bad files: exit 1, the file and the line named, the output untouched.
  fs::remove(dir / "d.json");
  const std::vector<std::pair<std::string, std::string>> bad{
      {"model-bias = 1\nmodel-sloop = 2\n", "line 2: unknown key 'model-sloop' (the keys: model-bias, "},
      {"model-bias = one\n", "line 1: model-bias = one is not a decimal number"},
      {"model-bias = 1\nmodel-bias = 2\n", "line 2: 'model-bias' is given twice, on lines 1 and 2"},
      {"model-bias 1\n", "line 1: expected 'key = value', got 'model-bias 1'"},
      {"model-bias =\n", "line 1: key 'model-bias' has no value"},
      {"[model]\nbias = 1\n", "line 1: section [model], but an INI file has no sections"},
      {"model-bias = 0\nmodel-slope = 1\n", "has no class-bias"},
      {std::string(kCalibrationIni)
           .replace(std::string(kCalibrationIni).find("none-slope = 0.5"), 16, "none-slope = 0"),
       "none-slope = 0 must be > 0"}};
  for (const auto& [text, message] : bad) {
    write(ini, text);
    CHECK(test::sh(cmd + " --calibration " + ini.string(), dir / "err.txt", &err) == 1);
    CHECK_THAT(err, Catch::Contains(ini.string() + ": ") && Catch::Contains(message));
    CHECK_FALSE(fs::exists(dir / "d.json"));
  }
  CHECK(test::sh(cmd + " --calibration " + (dir / "nope.ini").string(), dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains((dir / "nope.ini").string()));
  // Not with the size-only ablation (its confidences are none of canopy's levels').
  write(ini, kCalibrationIni);
  CHECK(test::sh(cmd + " --size-only --modelbase " + dir.string() + " --calibration " + ini.string(),
                 dir / "err.txt", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--calibration"));
}

TEST_CASE("collect --calibration: verify's none states its map by the candidate's density (verify.md §19)") {
  // By hand, verify's none at 0.9 (logit ln 9 = 2.19722): none-coarse (-1, 0.8): logistic(0.75778) =
  // 0.68087; none-dense (1, 1.2): logistic(3.63667) = 0.97434; none (-0.5, 0.5), the one map of
  // the ablation: logistic(0.59861) = 0.64534.
  const collect::Calibration cal = collect::parse_calibration(kCalibrationIni, "cal.ini");
  CHECK(cal.none_coarse.bias == -1);
  CHECK(cal.none_coarse.slope == 0.8);
  CHECK(cal.none_dense.bias == 1);
  CHECK(cal.none_dense.slope == 1.2);
  const double coarse = 0.6808715, dense = 0.9743361, unsplit = 0.6453388;
  collect::Inputs in;
  in.index.name = "idx.json";
  // Object densities: 120 and 369.9 (coarse: below the density rule's 370), 370 and 2800 (not),
  // c5 unknown (an older index: not coarse), c6 at 120 answered by classify's none alone.
  const std::vector<std::pair<const char*, std::optional<double>>> dens{
      {"c1", 120.0}, {"c2", 369.9}, {"c3", 370.0}, {"c4", 2800.0}, {"c5", std::nullopt}, {"c6", 120.0}};
  for (const auto& [id, d] : dens) {
    collect::Candidate c;
    c.id = id;
    c.transform = {1, 0, 0, E, 0, 1, 0, N, 0, 0, 1, 0, 0, 0, 0, 1};
    c.density = d;
    in.index.candidates.push_back(c);
  }
  in.provenance = {"collect", "9.9", {}, {"idx.json"}};
  in.answers = {
      // c1, c3: both levels none; c2, c4, c5: verify's none, classify did not answer.
      {answer("c1", "", "", "", 0.9), answer("c1", "class", "", "", 0.999, "too_small")},
      {answer("c2", "", "", "", 0.9), collect::absent_verdict("c2/class.json")},
      {answer("c3", "", "", "", 0.9), answer("c3", "class", "", "", 0.999, "not_vehicle_shape")},
      {answer("c4", "", "", "", 0.9), collect::absent_verdict("c4/class.json")},
      {answer("c5", "", "", "", 0.9), collect::absent_verdict("c5/class.json")},
      // c6: the model chain did not run: classify's none, the none-class map whatever the density.
      {collect::absent_verdict("c6/verdict.json"), answer("c6", "class", "", "", 0.25, "not_vehicle_shape")}};
  collect::Params p;
  CHECK(p.coarse_none_below == 370);  // the density rule's dense end, common::kDenseDensity
  p.calibration = cal;
  auto stated = [&] {
    const Json d = Json::parse(collect::run(p, in).detections);
    REQUIRE(d["rejected"].size() == 6);
    std::vector<double> out;
    for (const auto& r : d["rejected"]) out.push_back(r["confidence"].get<double>());
    return out;
  };
  const std::vector<double> split = stated();
  CHECK(split[0] == Approx(coarse).epsilon(1e-6));
  CHECK(split[1] == Approx(coarse).epsilon(1e-6));
  CHECK(split[2] == Approx(dense).epsilon(1e-6));
  CHECK(split[3] == Approx(dense).epsilon(1e-6));
  CHECK(split[4] == Approx(dense).epsilon(1e-6));
  CHECK(split[5] == Approx(0.20621089).epsilon(1e-7));
  // The ablation (--coarse-none-below 0): every verify none through the one none map, as before
  // §19; classify's none unchanged.
  p.coarse_none_below = 0;
  const std::vector<double> off = stated();
  for (int i = 0; i < 5; ++i) CHECK(off[i] == Approx(unsplit).epsilon(1e-6));
  CHECK(off[5] == split[5]);
  // Another line moves the split with it (an unknown density stays dense).
  p.coarse_none_below = 3000;
  const std::vector<double> high = stated();
  for (int i = 0; i < 4; ++i) CHECK(high[i] == Approx(coarse).epsilon(1e-6));
  CHECK(high[4] == Approx(dense).epsilon(1e-6));
  // Without a calibration the split changes nothing: verify's own 0.9.
  p.calibration = collect::Calibration{};
  p.coarse_none_below = 370;
  for (int i = 0; i < 5; ++i) CHECK(stated()[i] == 0.9);
  // Only the confidences differ between the split and the ablation.
  p.calibration = cal;
  const Json a = Json::parse(collect::run(p, in).detections);
  p.coarse_none_below = 0;
  CHECK(without_confidences(a) == without_confidences(Json::parse(collect::run(p, in).detections)));
}

TEST_CASE("collect --coarse-none-below on the command line; a calibration file without the density maps") {
  // The tile of tile(): c0002 is verify's none at 0.7 on a candidate 3 m x 2 m; with 600 object
  // points it has 100 points/m² (coarse), with 3000 points 500 (dense).
  const fs::path dir = tile("coarse-none");
  const fs::path cands = dir / "cands";
  Json index = read_json(cands / "index.json");
  const fs::path ini = dir / "cal.ini";
  write(ini, kCalibrationIni);
  const double l = std::log(0.7 / 0.3);
  const double coarse = 1 / (1 + std::exp(1 - 0.8 * l)), dense = 1 / (1 + std::exp(-1 - 1.2 * l)),
               unsplit = 1 / (1 + std::exp(0.5 - 0.5 * l));
  const std::string cmd = bin() + " -i " + (cands / "index.json").string() + " -o " +
                          (dir / "d.json").string() + " --calibration " + ini.string();
  std::string err;
  for (const auto& [points, expected, option] :
       std::vector<std::tuple<int, double, std::string>>{{600, coarse, ""},
                                                         {3000, dense, ""},
                                                         {600, unsplit, " --coarse-none-below 0"},
                                                         {3000, unsplit, " --coarse-none-below=0"},
                                                         {3000, coarse, " --coarse-none-below 600"}}) {
    index["candidates"][1]["object_points"] = points;
    write(cands / "index.json", index.dump());
    REQUIRE(test::sh(cmd + option, dir / "err.txt", &err) == 0);
    const Json d = read_json(dir / "d.json");
    CHECK(d["rejected"][0]["candidate"] == "c0002");
    CHECK(d["rejected"][0]["confidence"].get<double>() == Approx(expected).epsilon(1e-9));
  }
  // Usage: a negative or non-numeric line is exit 2, naming the option.
  for (const char* bad : {" --coarse-none-below -1", " --coarse-none-below x"}) {
    CHECK(test::sh(cmd + bad, dir / "err.txt", &err) == 2);
    CHECK_THAT(err, Catch::Contains("--coarse-none-below"));
  }
  // A calibration file of before §19 (the eight keys, no density maps) is refused by name.
  std::string old = kCalibrationIni;
  old = old.substr(0, old.find("none-dense-bias"));
  write(ini, old);
  fs::remove(dir / "d.json");
  CHECK(test::sh(cmd, dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains(ini.string() + ": ") && Catch::Contains("has no none-dense-bias"));
  CHECK_FALSE(fs::exists(dir / "d.json"));
}

TEST_CASE(
    "collect --class-accept: a class answer stating less is rejected as low_confidence; model answers stay") {
  const fs::path dir = tile("class_accept");
  const fs::path cands = dir / "cands";
  // c0001: verify's model answer sedan at 0.05 (a model answer: never judged by --class-accept).
  write(cands / "c0001" / "verdict.json", verdict((cands / "c0001" / "samples.pcd").string(), "sedan", 0.05,
                                                  flat(0, 0, 0, 0), flat(30, E + 10.25, N + 10.125, 100.5))
                                              .dump());
  // c0002: the model chain said none; classify a hatchback (group car) at 0.05.
  // c0003: no model chain (a class-level candidate); classify a van at 0.5.
  auto class_at = [&](const std::string& id, const char* cls, const char* group, double confidence) {
    Json k = class_answer(cands, id, cls, group, nullptr, 30, flat(90, 1, 0.5, 0));
    k["confidence"] = confidence;
    write(cands / id / "class.json", k.dump());
  };
  class_at("c0002", "hatchback", "car", 0.05);
  fs::remove(cands / "c0003" / "verdict.json");
  class_at("c0003", "van", "van", 0.5);
  const std::string cmd = bin() + " -i " + (cands / "index.json").string() + " -o " + (dir / "d.json").string();
  std::string err;
  auto run = [&](const std::string& options) {
    REQUIRE(test::sh(cmd + options, dir / "err.txt", &err) == 0);
    return read_json(dir / "d.json");
  };
  // What became of each candidate: "model sedan", "class hatchback", or the rejection's reason.
  auto answers = [](const Json& d) {
    std::map<std::string, std::string> a;
    for (const auto& x : d["detections"])
      a[x["candidate"]] = x["level"].get<std::string>() + " " +
                          (x["model"].is_null() ? x["class"] : x["model"]).get<std::string>();
    for (const auto& x : d["rejected"]) a[x["candidate"]] = x["reason"];
    return a;
  };
  using Answers = std::map<std::string, std::string>;
  // Off (the default, and 0 given): every class answer a detection, whatever it states.
  const Json off = run("");
  CHECK(answers(off) ==
        Answers{{"c0001", "model sedan"}, {"c0002", "class hatchback"}, {"c0003", "class van"}});
  CHECK(off["detections"][1]["confidence"] == 0.05);
  CHECK(off["provenance"]["parameters"]["class-accept"] == "0");
  CHECK(run(" --class-accept 0") == off);
  // 0.1: the 0.05 class answer is rejected; the 0.5 one and the 0.05 model answer stay.
  const Json d = run(" --class-accept 0.1");
  CHECK(answers(d) == Answers{{"c0001", "model sedan"}, {"c0002", "low_confidence"}, {"c0003", "class van"}});
  CHECK(d["found"] == 2);
  CHECK(d["by_level"] == Json{{"model", 1}, {"class", 1}});
  CHECK(d["by_reason"] == Json{{"low_confidence", 1}});
  CHECK(d["none"] == 1);
  CHECK(d["warning"].is_null());  // 1 of 3
  CHECK_THAT(err,
             Catch::Contains("2 vehicles found (1 model level, 1 class level); rejected: low_confidence 1"));
  REQUIRE(d["rejected"].size() == 1);
  const Json& r = d["rejected"][0];
  CHECK(r["candidate"] == "c0002");
  CHECK(r["detail"] ==
        "classify's class answer hatchback (car) states confidence 0.050, below collect --class-accept 0.1: "
        "not a "
        "detection");
  CHECK(r["confidence"].is_null());  // its confidence was in the class, not in a none
  CHECK(r["model_chain"] == "none");
  CHECK(r["density"] == 30.0);
  CHECK(r["verdict"] == (cands / "c0002" / "class.json").string());
  CHECK(r["position"]["x"].get<double>() == Approx(E + 5));
  // 0.5 is not below 0.5; just above it, the van goes too, and most candidates are rejected so.
  CHECK(answers(run(" --class-accept 0.5"))["c0003"] == "class van");
  const Json most = run(" --class-accept 0.51");
  CHECK(answers(most) ==
        Answers{{"c0001", "model sedan"}, {"c0002", "low_confidence"}, {"c0003", "low_confidence"}});
  CHECK(most["rejected"][1]["detail"] ==
        "classify's class answer van states confidence 0.500, below collect --class-accept 0.51: not a "
        "detection");
  CHECK(most["rejected"][1]["model_chain"].is_null());  // the model chain did not run
  CHECK(most["warning"] ==
        "2 of 3 candidates rejected as low_confidence: their class answers state a confidence below collect "
        "--class-accept; see docs/decisions/classify.md");
  // The stated confidence is the calibrated one: class (2, 1) at 0.05 = logistic(2 + ln(0.05 / 0.95)) = 0.2800.
  const fs::path ini = dir / "cal.ini";
  write(ini, kCalibrationIni);
  const Json cal = run(" --class-accept 0.1 --calibration " + ini.string());
  CHECK(answers(cal)["c0002"] == "class hatchback");
  CHECK(cal["detections"][1]["confidence"].get<double>() ==
        Approx(1 / (1 + std::exp(-2 - std::log(0.05 / 0.95)))).epsilon(1e-9));
  const Json cal3 = run(" --class-accept 0.3 --calibration " + ini.string());
  CHECK(answers(cal3)["c0002"] == "low_confidence");
  CHECK_THAT(cal3["rejected"][0]["detail"].get<std::string>(),
             Catch::Contains("states confidence 0.280, below collect --class-accept 0.3"));
  // A class answer that set aside a doubtful model answer (--contradicted-below) and states too
  // little: neither is a detection, and the rejection says what was set aside.
  Json v = verdict((cands / "c0002" / "samples.pcd").string(), "van__bus", 0.3, flat(0, 0, 0, 0),
                   flat(30, E + 10.25, N + 10.125, 100.5));
  v["class"] = "van";
  v["nearest_instance"] = "van__bus";
  v["class_score"] = 0.5;
  v["class_margin"] = 0.1;
  write(cands / "c0002" / "verdict.json", v.dump());
  CHECK(answers(run(""))["c0002"] == "class hatchback");
  const Json aside = run(" --class-accept 0.1");
  CHECK(answers(aside)["c0002"] == "low_confidence");
  CHECK(aside["rejected"][0]["model_chain"] == "set_aside");
  CHECK_THAT(aside["rejected"][0]["detail"].get<std::string>(),
             Catch::EndsWith("not a detection; the model chain's van__bus (confidence 0.30) set aside for it "
                             "(collect --contradicted-below)"));
  // The INI key of --config.
  write(dir / "collect.ini", "class-accept = 0.1\n");
  CHECK(answers(run(" --config " + (dir / "collect.ini").string()))["c0002"] == "low_confidence");
  // The range: [0, 1]; a usage error (exit 2) outside, nothing written.
  fs::remove(dir / "d.json");
  for (const char* bad : {"1.5", "-0.1", "nan"}) {
    CHECK(test::sh(cmd + " --class-accept " + bad, dir / "err.txt", &err) == 2);
    CHECK_FALSE(fs::exists(dir / "d.json"));
  }
  CHECK(test::sh(cmd + " --class-accept 1.5", dir / "err.txt", &err) == 2);
  CHECK_THAT(err, Catch::Contains("--class-accept must be in [0, 1]"));
  CHECK(test::sh(cmd + " --class-accept 1", dir / "err.txt", &err) == 0);
  // Not with the size-only ablation (none of classify's decisions).
  CHECK(test::sh(cmd + " --size-only --modelbase " + dir.string() + " --class-accept 0.1", dir / "err.txt",
                 &err) == 2);
  CHECK_THAT(err, Catch::Contains("--class-accept is canopy's class level's: not with --size-only"));
}

TEST_CASE("collect v2: a tile of one candidate, too sparse: the warning's count is singular") {
  const fs::path dir = tile("one_sparse");
  const fs::path cands = dir / "cands";
  Json index = read_json(cands / "index.json");
  index["density"] = Json{{"all", 5.0}, {"ground", 3.0}, {"first", nullptr}};
  index["candidates"] = Json::array({index["candidates"][0]});
  write(cands / "index.json", index.dump());
  fs::remove_all(cands / "c0002");
  fs::remove_all(cands / "c0003");
  fs::remove(cands / "c0001" / "verdict.json");
  write(cands / "c0001" / "class.json",
        class_answer(cands, "c0001", nullptr, nullptr, "too_sparse", 2.0, nullptr).dump());
  std::string err;
  REQUIRE(test::sh(bin() + " -i " + (cands / "index.json").string() + " -o " + (dir / "d.json").string(),
                   dir / "err.txt", &err) == 0);
  const Json d = read_json(dir / "d.json");
  CHECK(d["candidates"] == 1);
  const std::string w = d["warning"];
  CHECK_THAT(w,
             Catch::StartsWith("1 of 1 candidate rejected as too_sparse (median object density 2 points/m²"));
  CHECK_THAT(w, Catch::Contains("open-ground density 3 points/m²: below the 370 points/m² that model-level "
                                "recognition needs; class-level answers at most"));
}

TEST_CASE("collect: failed model chains are counted and said, whatever answered the candidates (stop 70)") {
  const fs::path dir = tile("chain_failed");
  const fs::path cands = dir / "cands";
  // Every model chain ran and failed (empty verdicts, stagerun --record-failure); classify
  // answered every candidate: c0001 a hatchback, c0002 and c0003 refused.
  for (const char* id : {"c0001", "c0002", "c0003"}) write(cands / id / "verdict.json", "");
  write(cands / "c0001" / "class.json",
        class_answer(cands, "c0001", "hatchback", "car", nullptr, 900, flat(0, 0, 0, 0)).dump());
  write(cands / "c0002" / "class.json",
        class_answer(cands, "c0002", nullptr, nullptr, "not_vehicle_shape", 900, nullptr).dump());
  write(cands / "c0003" / "class.json",
        class_answer(cands, "c0003", nullptr, nullptr, "vegetation_like", 900, nullptr).dump());
  // c0001's chain: fitvox wrote its samples, cocone failed first (its mesh.ply empty), the later
  // stages failed on it in turn.
  write(cands / "c0001" / "samples.pcd", "not empty");
  for (const char* a : {"mesh.ply", "segments.json", "match.json"}) write(cands / "c0001" / a, "");
  const std::string cmd = bin() + " -i " + (cands / "index.json").string() + " -o " + (dir / "d.json").string();
  std::string err;
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);  // a warning, not an error (real-tiles.md, stop 70)
  Json d = read_json(dir / "d.json");
  // The counts keep their meaning: no rejection is for a failed chain (classify answered them).
  CHECK(d["found"] == 1);
  CHECK(d["failed"] == 0);
  CHECK(d["none"] == 2);
  CHECK(d["by_reason"] == Json{{"not_vehicle_shape", 1}, {"vegetation_like", 1}});
  // What the counts hid, counted apart.
  CHECK(d["model_chain_ran"] == 3);
  CHECK(d["model_chain_failed"] == 3);
  const documents::Detections back = documents::read_detections_file((dir / "d.json").string());
  CHECK(back.model_chain_ran == 3);
  CHECK(back.model_chain_failed == 3);
  CHECK(back.failed == 0);
  CHECK_THAT(err, Catch::Contains("collect: 3 candidates: 1 vehicle found (0 model level, 1 class level); "
                                  "rejected: not_vehicle_shape 1, vegetation_like 1; model chain failed on 3 "
                                  "of the 3 candidates it ran on\n"));
  const std::string first_log = (cands / "c0001" / "mesh.ply.log").string();
  CHECK(d["warning"] ==
        "the model chain failed on all 3 candidates it ran on: the model level decided "
        "nothing here, the answers are classify's alone (the log of the first failed stage "
        "of c0001: " +
            first_log + "); see docs/decisions/classify.md");
  CHECK_THAT(err, Catch::Contains("collect: warning: the model chain failed on all 3 candidates"));
  // Most, not all: c0002's chain found nothing. The example is the first failed candidate; c0003
  // has no chain artifact beside its verdict: its verdict's own log is named.
  write(cands / "c0002" / "verdict.json",
        verdict((cands / "c0002" / "samples.pcd").string(), nullptr, 0.7, nullptr, nullptr).dump());
  fs::remove_all(cands / "c0001");
  write(cands / "c0001" / "verdict.json", "");
  write(cands / "c0001" / "class.json",
        class_answer(cands, "c0001", "hatchback", "car", nullptr, 900, flat(0, 0, 0, 0)).dump());
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  d = read_json(dir / "d.json");
  CHECK(d["model_chain_ran"] == 3);
  CHECK(d["model_chain_failed"] == 2);
  CHECK_THAT(err, Catch::Contains("; model chain failed on 2 of the 3 candidates it ran on\n"));
  CHECK(d["warning"] ==
        "the model chain failed on 2 of the 3 candidates it ran on: those are answered by "
        "classify alone (the log of the first failed stage of c0001: " +
            (cands / "c0001" / "verdict.json.log").string() + "); see docs/decisions/classify.md");
  // One of three: counted in the summary, no warning.
  write(cands / "c0001" / "verdict.json", verdict((cands / "c0001" / "samples.pcd").string(), "sedan", 0.9,
                                                  flat(0, 0, 0, 0), flat(30, E + 10.25, N + 10.125, 100.5))
                                              .dump());
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  d = read_json(dir / "d.json");
  CHECK(d["model_chain_failed"] == 1);
  CHECK(d["warning"].is_null());
  CHECK_THAT(err, Catch::Contains("; model chain failed on 1 of the 3 candidates it ran on\n"));
  // None failed: the summary says nothing of it, the counts are there.
  write(cands / "c0003" / "verdict.json",
        verdict((cands / "c0003" / "samples.pcd").string(), nullptr, 0.7, nullptr, nullptr).dump());
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  d = read_json(dir / "d.json");
  CHECK(d["model_chain_ran"] == 3);
  CHECK(d["model_chain_failed"] == 0);
  CHECK_THAT(err, !Catch::Contains("model chain failed"));
  // A class-level candidate (no verdict.json) is not one the chain ran on; one candidate: singular.
  fs::remove(cands / "c0002" / "verdict.json");
  fs::remove(cands / "c0003" / "verdict.json");
  write(cands / "c0001" / "verdict.json", "");
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  d = read_json(dir / "d.json");
  CHECK(d["model_chain_ran"] == 1);
  CHECK(d["model_chain_failed"] == 1);
  CHECK_THAT(err, Catch::Contains("; model chain failed on 1 of the 1 candidate it ran on\n"));
  CHECK_THAT(
      d["warning"].get<std::string>(),
      Catch::StartsWith("the model chain failed on the one candidate it ran on: the model level decided "
                        "nothing here"));
}

TEST_CASE("collect: failed_stage_log names the first empty artifact of the chain, else the verdict's log") {
  const fs::path dir = test::fresh_dir("collect", "stage_log") / "c0001";
  const std::string verdict = (dir / "verdict.json").string();
  write(dir / "verdict.json", "");
  CHECK(collect::failed_stage_log(verdict) == verdict + ".log");
  write(dir / "match.json", "");
  CHECK(collect::failed_stage_log(verdict) == (dir / "match.json.log").string());
  write(dir / "samples.pcd", "");
  CHECK(collect::failed_stage_log(verdict) == (dir / "samples.pcd.log").string());
  write(dir / "samples.pcd", "x");  // fitvox wrote its samples: ncut's, gmatch's, ... is first
  write(dir / "segments.json", "");
  CHECK(collect::failed_stage_log(verdict) == (dir / "segments.json.log").string());
  CHECK(collect::read_verdict(verdict).failed_log == (dir / "segments.json.log").string());
  CHECK(collect::parse_verdict("", verdict).failed_log.empty());  // not looked for: the verdict's log
}

TEST_CASE("collect: a tile without candidates says why; detect's warnings are relayed (stop 70)") {
  const fs::path dir = test::fresh_dir("collect", "no_candidates");
  const fs::path cands = dir / "cands";
  Json index{{"format", "canopy.candidates"},
             {"version", 2},
             {"tile", "tile.las"},
             {"density",
              {{"all", 2.5}, {"ground", 1.5}, {"first", nullptr}, {"cell", 1.0}, {"occupied_cells", 25000}}},
             {"candidates", Json::array()}};
  write(cands / "index.json", index.dump());
  const std::string cmd = bin() + " -i " + (cands / "index.json").string() + " -o " + (dir / "d.json").string();
  std::string err;
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  Json d = read_json(dir / "d.json");
  CHECK(d["candidates"] == 0);
  CHECK(d["model_chain_ran"] == 0);
  const std::string sparse =
      "no candidate on this tile of 2.5 ha: its open-ground density 1.5 points/m² is below the 4 points/m² "
      "the class level needs on an object (classify --min-density): too sparse for vehicles to be found; ";
  CHECK(d["warning"] == sparse + "a denser survey is the remedy");
  CHECK_THAT(err,
             Catch::Contains("collect: 0 candidates: 0 vehicles found (0 model level, 0 class level)\n"));
  CHECK_THAT(err, Catch::Contains("collect: warning: no candidate on this tile of 2.5 ha: its open-ground"));
  // Dense enough: detect found nothing of a vehicle's size.
  index["density"]["ground"] = 30.0;
  index["density"]["occupied_cells"] = 4000;
  write(cands / "index.json", index.dump());
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  CHECK(
      read_json(dir / "d.json")["warning"] ==
      "no candidate on this tile of 0.40 ha (open-ground density 30 points/m²): detect found no object of a "
      "vehicle's size and height between the ground and the canopy (detect's log counts the objects it "
      "rejected)");
  // No open-ground density: all returns', said so.
  index["density"]["ground"] = nullptr;
  write(cands / "index.json", index.dump());
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  CHECK_THAT(read_json(dir / "d.json")["warning"].get<std::string>(),
             Catch::StartsWith("no candidate on this tile of 0.40 ha: its tile density 2.5 points/m² (all "
                               "returns) is below the 4 points/m²"));
  // A tile in feet: detect's warning (in the index) leads, and the remedy points to it.
  index["density"]["ground"] = 1.5;
  index["density"]["occupied_cells"] = 25000;
  const std::string feet =
      "tile.las: its georeferencing gives the coordinates in foot (0.3048 m) (GeoTIFF key ProjLinearUnits = "
      "9002); detect reads them as metres, so every length (DTM cell, vehicle ranges) is taken in foot: "
      "convert the tile to metres first";
  index["warnings"] = Json::array({feet});
  write(cands / "index.json", index.dump());
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  CHECK(
      read_json(dir / "d.json")["warning"] ==
      "detect warned: " + feet +
          "; no candidate on this tile of 2.5 ha (its area and density as detect read its coordinates): its "
          "open-ground density 1.5 points/m² is below the 4 points/m² the class level needs on an object "
          "(classify --min-density): too sparse for vehicles to be found; see detect's warning first");
  CHECK_THAT(err, Catch::Contains("collect: warning: detect warned: tile.las: its georeferencing"));
  // An index without detect's density (an older detect) still says there is nothing.
  index.erase("density");
  index.erase("warnings");
  write(cands / "index.json", index.dump());
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  CHECK(read_json(dir / "d.json")["warning"] ==
        "no candidate on this tile (the index states no density: an older detect)");
  // A tile with candidates whose answers alone would give no warning: detect's is relayed.
  const fs::path t = tile("detect_warned");
  Json i3 = read_json(t / "cands" / "index.json");
  i3["warnings"] =
      Json::array({"tile.las: LASF_Projection 2112 (OGC WKT): the WKT's PROJCS names no EPSG code"});
  write(t / "cands" / "index.json", i3.dump());
  REQUIRE(test::sh(bin() + " -i " + (t / "cands" / "index.json").string() + " -o " + (t / "d.json").string(),
                   t / "err.txt", &err) == 0);
  CHECK(read_json(t / "d.json")["warning"] ==
        "detect warned: tile.las: LASF_Projection 2112 (OGC WKT): the WKT's PROJCS names no EPSG code");
  // "warnings" must be an array of sentences: named, nothing written.
  i3["warnings"] = Json::array({1});
  write(t / "cands" / "index.json", i3.dump());
  fs::remove(t / "d.json");
  CHECK(test::sh(bin() + " -i " + (t / "cands" / "index.json").string() + " -o " + (t / "d.json").string(),
                 t / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("warnings[0]"));
  CHECK_FALSE(fs::exists(t / "d.json"));
}

TEST_CASE("collect: the density a tile without candidates is stated against is classify's default") {
  CHECK(collect::kClassDensity == classify::Params{}.min_density);
}
