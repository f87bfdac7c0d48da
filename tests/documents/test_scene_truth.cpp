// documents/scene_truth.h: truth.json (canopy.scene_truth v1) as rangetrace writes it and as the
// hand labels of share/real are written, read by score, topview and report through one reader.
#include <catch2/catch.hpp>

#include <string>

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
}
