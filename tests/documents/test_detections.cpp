// documents/detections.h: a tile's detections.json (canopy.detections v1 and v2), read by
// score, topview and report through one reader. Hand-written documents read to the values they
// hold; malformed ones are refused naming the file and the member.
#include <catch2/catch.hpp>

#include <string>

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/documents/detections.h"

using namespace canopy;
using Json = nlohmann::ordered_json;

namespace {

// As collect writes it (version 2): one model-level and one class-level detection, one rejection.
const char* kV2 = R"({"format": "canopy.detections", "version": 2,
 "provenance": {"tool": "collect", "version": "0.1.0", "parameters": {}, "inputs": []},
 "index": "cands/index.json", "tile": "tile.pcd", "crs": "EPSG:32633",
 "candidates": 3, "found": 2, "none": 0, "failed": 0,
 "by_level": {"model": 1, "class": 1}, "by_reason": {"too_sparse": 1},
 "density": {"all": 120.5, "ground": null}, "warning": null,
 "detections": [
  {"candidate": "c0001", "level": "model", "model": "sedan", "class": "sedan", "group": "car",
   "confidence": 0.75, "pose": {"x": 500010.25, "y": 5400010.5, "z": 100.0, "heading": 30.0, "pitch": 0.0,
   "roll": 0.0, "matrix": []}, "footprint": [[0, 0], [4, 0], [4, 2], [0, 2]], "footprint_from": "model",
   "verdict": "cands/c0001/verdict.json"},
  {"candidate": "c0003", "level": "class", "model": null, "class": "van", "group": "van", "confidence": 0.5,
   "pose": {"x": 500020.0, "y": 5400020.0, "z": 100.0, "heading": 90.0}, "heading_ambiguity_deg": 180.0,
   "size": null, "density": 60.0, "footprint": [[1, 1], [2, 1], [2, 3]], "footprint_from": "class",
   "verdict": "cands/c0003/class.json"}],
 "rejected": [{"candidate": "c0002", "reason": "too_sparse", "detail": null, "confidence": 0.9}]}
)";

// An early version 1 document: no levels, none and failed counted, no rejections listed.
const char* kV1 = R"({"format": "canopy.detections", "version": 1, "candidates": 4, "none": 2, "failed": 1,
 "detections": [{"candidate": "c1", "model": "tank", "confidence": 1,
                 "pose": {"x": 1, "y": 2, "z": 3, "heading": -45}}]})";

std::string refusal(const Json& doc) {
  try {
    documents::read_detections(doc.dump(), "tile/detections.json");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "tile/detections.json");
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("detections: version 2 as collect writes it reads to its values") {
  const documents::Detections d = documents::read_detections(kV2, "detections.json");
  CHECK(d.version == 2);
  CHECK(d.index == "cands/index.json");
  CHECK(d.tile == "tile.pcd");
  CHECK(d.candidates == 3);
  CHECK(d.found == 2);
  CHECK(d.by_level == std::map<std::string, int>{{"class", 1}, {"model", 1}});
  CHECK(d.by_reason == std::map<std::string, int>{{"too_sparse", 1}});
  CHECK(d.warning == std::string());
  CHECK(d.density_all() == 120.5);
  REQUIRE(d.detections.size() == 2);
  const documents::Detection& m = d.detections[0];
  CHECK(m.candidate == "c0001");
  CHECK(m.level == "model");
  CHECK(m.model == "sedan");
  CHECK(m.group == "car");
  CHECK(m.confidence == 0.75);
  REQUIRE(m.pose);
  CHECK(m.pose->x == 500010.25);
  CHECK(m.pose->heading == 30.0);
  CHECK(m.footprint == std::vector<std::array<double, 2>>{{0, 0}, {4, 0}, {4, 2}, {0, 2}});
  const documents::Detection& c = d.detections[1];
  CHECK(c.level == "class");
  CHECK(c.model.empty());
  CHECK(c.cls == "van");
  CHECK(c.footprint.size() == 3);
  REQUIRE(d.has_rejected);
  REQUIRE(d.rejected.size() == 1);
  CHECK(d.rejected[0].candidate == "c0002");
  CHECK(d.rejected[0].reason == std::string("too_sparse"));
}

TEST_CASE("detections: version 1 reads without levels (model level) and without rejections") {
  const documents::Detections d = documents::read_detections(kV1, "detections.json");
  CHECK(d.version == 1);
  CHECK(d.candidates == 4);
  CHECK(d.none == 2);
  CHECK(d.failed == 1);
  CHECK_FALSE(d.found);
  CHECK_FALSE(d.by_reason);
  CHECK_FALSE(d.warning);
  CHECK_FALSE(d.density_all());
  REQUIRE(d.detections.size() == 1);
  CHECK(d.detections[0].level == "model");
  CHECK(d.detections[0].pose->heading == -45);
  CHECK(d.detections[0].footprint.empty());
  CHECK_FALSE(d.has_rejected);
  Json v1_class = Json::parse(kV1);
  v1_class["detections"][0]["model"] = nullptr;
  v1_class["detections"][0]["group"] = "car";
  CHECK(documents::read_detections(v1_class.dump(), "d.json").detections[0].level == "class");
}

TEST_CASE("detections: refusals name the file and the problem") {
  const Json good = Json::parse(kV2);
  CHECK(refusal(good).empty());
  Json other = good, version = good, no_list = good, no_level = good, level = good, conf = good, twice = good,
       corner = good, count = good, warning = good, reason = good, pose = good, classless = good;
  other["format"] = "canopy.verdict";
  version["version"] = 3;
  no_list.erase("detections");
  no_level["detections"][1].erase("level");
  level["detections"][0]["level"] = "part";
  conf["detections"][0]["confidence"] = 1.5;
  twice["detections"][1]["candidate"] = "c0001";
  corner["detections"][0]["footprint"][2] = Json::array({4});
  count["found"] = -2;
  warning["warning"] = 3;
  reason["rejected"][0]["reason"] = 3;
  pose["detections"][1]["pose"].erase("y");
  classless["detections"][1]["class"] = nullptr;
  classless["detections"][1]["group"] = nullptr;
  CHECK_THAT(refusal(other), Catch::Contains("canopy.verdict"));
  CHECK_THAT(refusal(version), Catch::Contains("version 3"));
  CHECK_THAT(refusal(no_list), Catch::Contains("missing \"detections\""));
  CHECK_THAT(refusal(no_level), Catch::Contains("detections[1]: missing \"level\""));
  CHECK_THAT(refusal(level), Catch::Contains("detections[0].level must be model or class, not \"part\""));
  CHECK_THAT(refusal(conf), Catch::Contains("detections[0].confidence must lie in [0, 1]"));
  CHECK_THAT(refusal(twice), Catch::Contains("detections[1].candidate \"c0001\" repeats"));
  CHECK_THAT(refusal(corner), Catch::Contains("detections[0].footprint[2] must be [x, y]"));
  CHECK_THAT(refusal(count), Catch::Contains("found must be a non-negative integer, not -2"));
  CHECK_THAT(refusal(warning), Catch::Contains("warning is neither a sentence nor null"));
  CHECK_THAT(refusal(reason), Catch::Contains("rejected[0].reason must be a string, not 3"));
  CHECK_THAT(refusal(pose), Catch::Contains("detections[1].pose: missing \"y\""));
  CHECK_THAT(refusal(classless), Catch::Contains("a class-level detection without a class or group"));
}
