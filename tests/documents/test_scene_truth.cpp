// documents/scene_truth.h: truth.json (canopy.scene_truth v1) as rangetrace writes it and as the
// hand labels of share/real are written, read by score, topview and report through one reader.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/documents/scene_truth.h"

using namespace canopy;
using Json = nlohmann::ordered_json;

namespace {

const char* kTruth = R"({"format": "canopy.scene_truth", "version": 1, "provenance": {}, "extent": [16.0, 12.5],
 "origin": [500000, 5400000, 200],
 "vehicles": [
  {"instance": 1, "model": "sedan", "class": "sedan", "pose": {"x": 500005.0, "y": 5400006.0, "z": 200.0,
   "heading": 30.0}, "canopy_cover": 0.25, "footprint": [[0, 0], [4, 0], [4, 2], [0, 2]]},
  {"instance": 4, "model": "van", "class": null, "pose": {"x": 1.5, "y": 2.5, "heading": 0},
   "canopy_cover": 1, "visibility": "partial"}],
 "uncertain": [{"id": "u1", "pose": {"x": 7.0, "y": 8.0}}]}
)";

std::string refusal(const Json& doc) {
  try {
    documents::read_scene_truth(doc.dump(), "a.truth.json");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "a.truth.json");
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("scene truth: a hand-written truth reads to its values") {
  const documents::SceneTruth t = documents::read_scene_truth(kTruth, "a.truth.json");
  REQUIRE(t.extent);
  CHECK((*t.extent)[0] == 16.0);
  CHECK((*t.extent)[1] == 12.5);
  REQUIRE(t.vehicles.size() == 2);
  const documents::TrueVehicle& a = t.vehicles[0];
  CHECK(a.instance == 1);
  CHECK(a.model == "sedan");
  CHECK(a.cls == "sedan");
  REQUIRE(a.pose);
  CHECK(a.pose->x == 500005.0);
  CHECK(a.pose->z == 200.0);
  CHECK(a.pose->heading == 30.0);
  CHECK(a.canopy_cover == 0.25);
  CHECK(a.footprint.size() == 4);
  const documents::TrueVehicle& b = t.vehicles[1];
  CHECK(b.cls.empty());
  CHECK(b.visibility == "partial");
  CHECK_FALSE(b.pose->z);
  CHECK(b.footprint.empty());
  REQUIRE(t.uncertain.size() == 1);
  CHECK(t.uncertain[0].x == 7.0);
  CHECK(t.uncertain[0].y == 8.0);
  CHECK_FALSE(t.pulses_per_m2);
  CHECK_FALSE(t.returns_per_m2);
  // A sensor-mode render's measured density.
  Json sensor = Json::parse(kTruth);
  sensor["density"] = {{"returns_per_m2", 33.5},
                       {"first_returns_per_m2", 26.4},
                       {"pulses_per_m2", 26.5},
                       {"pulses_by_returns", Json::array({0, 10, 2})}};
  const documents::SceneTruth s = documents::read_scene_truth(sensor.dump(), "s.truth.json");
  CHECK(s.pulses_per_m2 == 26.5);
  CHECK(s.returns_per_m2 == 33.5);
}

TEST_CASE("scene truth: refusals name the file and the problem") {
  const Json good = Json::parse(kTruth);
  CHECK(refusal(good).empty());
  Json other = good, version = good, no_list = good, no_instance = good, twice = good, negative = good,
       cover = good, extent = good, pose = good, corner = good, uncertain = good, model = good;
  other["format"] = "canopy.scene_score";
  version["version"] = 2;
  no_list.erase("vehicles");
  no_instance["vehicles"][1].erase("instance");
  twice["vehicles"][1]["instance"] = 1;
  negative["vehicles"][0]["instance"] = -1;
  cover["vehicles"][0]["canopy_cover"] = 1.5;
  extent["extent"] = Json::array({16.0, 0.0});
  pose["vehicles"][0]["pose"].erase("y");
  corner["vehicles"][0]["footprint"][1] = "x";
  uncertain["uncertain"][0].erase("pose");
  model["vehicles"][0]["model"] = 3;
  CHECK_THAT(refusal(other), Catch::Contains("canopy.scene_score"));
  CHECK_THAT(refusal(version), Catch::Contains("version 2"));
  CHECK_THAT(refusal(no_list), Catch::Contains("missing \"vehicles\""));
  CHECK_THAT(refusal(no_instance), Catch::Contains("vehicles[1]: missing \"instance\""));
  CHECK_THAT(refusal(twice), Catch::Contains("vehicles[1].instance 1 repeats"));
  CHECK_THAT(refusal(negative),
             Catch::Contains("vehicles[0].instance must be a non-negative integer, not -1"));
  CHECK_THAT(refusal(cover), Catch::Contains("vehicles[0].canopy_cover must lie in [0, 1]"));
  CHECK_THAT(refusal(extent), Catch::Contains("extent must be positive"));
  CHECK_THAT(refusal(pose), Catch::Contains("vehicles[0].pose: missing \"y\""));
  CHECK_THAT(refusal(corner), Catch::Contains("vehicles[0].footprint[1] must be [x, y], not \"x\""));
  CHECK_THAT(refusal(uncertain), Catch::Contains("uncertain[0]: missing \"pose\""));
  CHECK_THAT(refusal(model), Catch::Contains("vehicles[0].model must be a string, not 3"));
  Json density = good, pulses = good;
  density["density"] = 3;
  pulses["density"] = {{"pulses_per_m2", -1}};
  CHECK_THAT(refusal(density), Catch::Contains("density must be an object"));
  CHECK_THAT(refusal(pulses), Catch::Contains("density.pulses_per_m2 must not be negative"));
}

TEST_CASE("scene truth: rangetrace's writer, byte for byte, and the reader reads what it wrote") {
  documents::RenderedTruth t;
  t.scene = "tile.ini";
  t.extent_x = 16;
  t.extent_y = 12.5;
  t.origin = documents::Point3{500000, 5400000, 200};
  t.terrain = "flat";
  t.angles = "degrees";
  documents::RenderedVehicle v;
  v.instance = 1;
  v.model = "sedan";
  v.line = 3;
  v.x = 500005;
  v.y = 5400006;
  v.z = 200;
  v.heading = 30;
  v.size = {4.5, 1.8, 1.4};
  v.footprint = {{0, 0}, {4, 0}, {4, 2}};
  v.canopy_cover = 0.25;
  documents::RenderedVehicle w = v;
  w.instance = 2;
  w.cls = "hatchback";
  w.footprint = {{1, 1}, {2, 1}, {2, 2}};
  t.vehicles = {v, w};
  t.clutter = {{"shed", {1, 2, 3}, {2, 2, 2}, 90, 0, 0}};
  t.broadleaf = 2;
  t.discs = 1;
  t.canopy_cover = 0.5;
  t.canopy_spacing = 0.25;
  t.images = {{0, 0, 1, 60, 0, {0, 0.5, 0.8660254037844386}, 200.5}};
  const std::string text =
      documents::write_scene_truth(t, {"rangetrace", "9.9", {{"seed", "7"}}, {"tile.ini"}});
  const Json j = Json::parse(text);
  CHECK(text.rfind("{\n  \"format\": \"canopy.scene_truth\",\n  \"version\": 1,\n  \"provenance\": {\n", 0) ==
        0);
  CHECK(text.back() == '\n');
  std::vector<std::string> keys;
  for (const auto& [k, x] : j.items()) keys.push_back(k);
  CHECK(keys == std::vector<std::string>{"format", "version", "provenance", "scene", "extent", "origin",
                                         "terrain", "angles", "vehicles", "clutter", "vegetation",
                                         "canopy_cover", "canopy_spacing", "images"});
  CHECK(j["provenance"].dump() ==
        R"({"tool":"rangetrace","version":"9.9","parameters":{"seed":"7"},"inputs":["tile.ini"]})");
  CHECK(
      j["vehicles"][0].dump() ==
      R"({"instance":1,"model":"sedan","line":3,"pose":{"x":500005.0,"y":5400006.0,"z":200.0,"heading":30.0,)"
      R"("pitch":0.0,"roll":0.0},"size":[4.5,1.8,1.4],"footprint":[[0.0,0.0],[4.0,0.0],[4.0,2.0]],"canopy_cover":0.25})");
  CHECK(j["vehicles"][1]["class"] == "hatchback");
  CHECK(j["clutter"][0].dump() ==
        R"({"kind":"shed","box":{"centre":[1.0,2.0,3.0],"size":[2.0,2.0,2.0],"heading":90.0,"pitch":0.0,"roll":0.0}})");
  CHECK(j["vegetation"].dump() == R"({"broadleaf":2,"conifer":0,"bushes":0,"discs":1})");
  CHECK(j["images"][0].dump() == R"({"view_idx":0,"heading":0.0,"flight_line":1,"elevation":60.0,"azimuth":0.0,)"
                                 R"("toward_sensor":[0.0,0.5,0.8660254037844386],"swath_area":200.5})");
  const documents::SceneTruth back = documents::read_scene_truth(text, "truth.json");
  REQUIRE(back.vehicles.size() == 2);
  CHECK(back.vehicles[1].cls == "hatchback");
  CHECK(back.vehicles[0].pose->heading == 30.0);
  CHECK((*back.extent)[1] == 12.5);

  // Sensor mode: sensor, flight_lines and density instead of images; a null origin and preset.
  t.origin.reset();
  documents::RenderedSensor s;
  s.keys = {{"altitude", "1000m"}};
  s.flight_lines = {{1, 90, -5, {0, 0, 1000}, {100, 0, 1000}, 10.5, 20.25}};
  s.returns_per_m2 = 12;
  s.first_returns_per_m2 = 10;
  s.pulses_per_m2 = 11;
  s.pulses_by_returns = {0, 7, 3};
  t.sensor = s;
  const Json k = Json::parse(documents::write_scene_truth(t, {}));
  CHECK(k["origin"].is_null());
  CHECK_FALSE(k.contains("images"));
  CHECK(k["sensor"].dump() == R"({"preset":null,"keys":{"altitude":"1000m"}})");
  CHECK(k["flight_lines"][0].dump() ==
        R"({"point_source_id":1,"heading":90.0,"offset":-5.0,"start":[0.0,0.0,1000.0],"end":[100.0,0.0,1000.0],)"
        R"("gps_time":[10.5,20.25]})");
  CHECK(k["density"].dump() ==
        R"({"returns_per_m2":12.0,"first_returns_per_m2":10.0,"pulses_per_m2":11.0,"pulses_by_returns":[0,7,3]})");
}
