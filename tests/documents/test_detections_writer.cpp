// documents/detections.h, the writer: collect's detections.json (canopy.detections v2) and its
// GeoJSON. Given what collect placed, it reproduces collect's output of d83b7b7 byte for byte,
// and the one detections reader reads it back.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "canopy/documents/detections.h"
#include "old_outputs.h"

using namespace canopy;
using Json = nlohmann::ordered_json;

namespace {

std::optional<double> number(const Json& j) {
  return j.is_null() ? std::nullopt : std::optional<double>(j.get<double>());
}
std::string text(const Json& j) { return j.is_null() ? "" : j.get<std::string>(); }

// What collect placed and counted, taken from its old output (the values, not the text).
documents::DetectionsRecord placed(const std::string& old) {
  const Json j = Json::parse(old);
  documents::DetectionsRecord r;
  const Json& prov = j["provenance"];
  r.provenance.tool = prov["tool"].get<std::string>();
  r.provenance.version = prov["version"].get<std::string>();
  for (const auto& [k, v] : prov["parameters"].items())
    r.provenance.parameters.emplace_back(k, v.get<std::string>());
  for (const auto& in : prov["inputs"]) r.provenance.inputs.push_back(in.get<std::string>());
  r.index = j["index"].get<std::string>();
  r.tile = j["tile"].get<std::string>();
  r.crs = text(j["crs"]);
  r.candidates = j["candidates"];
  r.found = j["found"];
  r.none = j["none"];
  r.failed = j["failed"];
  r.model_level = j["by_level"]["model"];
  r.class_level = j["by_level"]["class"];
  for (const auto& [k, v] : j["by_reason"].items()) r.by_reason[k] = v;
  r.density = j["density"];
  r.warning = text(j["warning"]);
  for (const Json& e : j["detections"]) {
    documents::DetectionRecord d;
    d.candidate = e["candidate"].get<std::string>();
    d.model_level = e["level"].get<std::string>() == "model";
    d.model = text(e["model"]);
    d.cls = e.contains("class") ? text(e["class"]) : "";
    d.group = e.contains("group") ? text(e["group"]) : "";
    d.confidence = e["confidence"];
    for (int i = 0; i < 16; ++i) d.matrix[i] = e["pose"]["matrix"][i];
    d.euler = {e["pose"]["heading"], e["pose"]["pitch"], e["pose"]["roll"]};
    if (!d.model_level) {
      d.heading_ambiguity = e["heading_ambiguity_deg"];
      if (!e["size"].is_null())
        d.size = std::array<double, 3>{e["size"]["length"], e["size"]["width"], e["size"]["height"]};
      d.density = number(e["density"]);
    }
    for (const Json& c : e["footprint"]) d.footprint.push_back({c[0].get<double>(), c[1].get<double>()});
    d.footprint_from = e["footprint_from"].get<std::string>();
    d.verdict = e["verdict"].get<std::string>();
    r.detections.push_back(d);
  }
  for (const Json& e : j["rejected"]) {
    documents::RejectionRecord x;
    x.candidate = e["candidate"].get<std::string>();
    x.reason = e["reason"].get<std::string>();
    if (!e["detail"].is_null()) x.detail = e["detail"].get<std::string>();
    x.confidence = number(e["confidence"]);
    x.density = number(e["density"]);
    x.classified = e.contains("model_chain");
    if (x.classified) {
      x.has_density_needed = !e["density_needed"].is_null();
      if (x.has_density_needed) {
        x.density_class = number(e["density_needed"]["class"]);
        x.density_model = number(e["density_needed"]["model"]);
      }
      if (!e["model_chain"].is_null()) x.model_chain = e["model_chain"].get<std::string>();
    }
    x.verdict = e["verdict"].get<std::string>();
    r.rejected.push_back(x);
  }
  return r;
}

}  // namespace

TEST_CASE("detections writer: reproduces collect's output of d83b7b7 byte for byte") {
  const documents::DetectionsRecord a = placed(old_output::kCollectClassLevel);
  CHECK(documents::serialize_detections(a) == old_output::kCollectClassLevel);
  CHECK(documents::serialize_detections_geojson(a) == old_output::kCollectClassLevelGeojson);
  const documents::DetectionsRecord b = placed(old_output::kCollectModelAndFailed);
  CHECK(documents::serialize_detections(b) == old_output::kCollectModelAndFailed);
  CHECK(documents::serialize_detections_geojson(b) == old_output::kCollectModelAndFailedGeojson);
}

TEST_CASE("detections writer: a hand-placed detection is read back by the one reader") {
  documents::DetectionsRecord r;
  r.provenance = {"collect", "9.9", {}, {"idx.json"}};
  r.index = "idx.json";
  r.tile = "tile.pcd";
  r.crs = "EPSG:32633";
  r.candidates = 2;
  r.found = 1;
  r.none = 1;
  r.model_level = 1;
  r.by_reason = {{"none", 1}};
  r.density = Json{{"all", 120.5}, {"ground", 100.0}};
  documents::DetectionRecord d;
  d.candidate = "c1";
  d.model = "sedan";
  d.cls = "sedan";
  d.confidence = 0.75;
  d.matrix = {0, -1, 0, 500010, 1, 0, 0, 5400020, 0, 0, 1, 100, 0, 0, 0, 1};
  d.euler = {90, 0, 0};
  d.footprint = {{500011, 5400018}, {500011, 5400022}, {500009, 5400022}, {500009, 5400018}};
  d.footprint_from = "model";
  d.verdict = "c1/verdict.json";
  r.detections = {d};
  documents::RejectionRecord x;
  x.candidate = "c2";
  x.reason = "none";
  x.detail = "the model chain found no model of the modelbase";
  x.confidence = 0.25;
  x.verdict = "c2/verdict.json";
  r.rejected = {x};
  const documents::Detections back = documents::read_detections(documents::serialize_detections(r), "d.json");
  CHECK(back.version == 2);
  CHECK(back.tile == "tile.pcd");
  CHECK(back.candidates == 2);
  CHECK(back.found == 1);
  CHECK(back.density_all() == 120.5);
  REQUIRE(back.detections.size() == 1);
  CHECK(back.detections[0].level == "model");
  CHECK(back.detections[0].model == "sedan");
  REQUIRE(back.detections[0].pose);
  CHECK(back.detections[0].pose->x == 500010);
  CHECK(back.detections[0].pose->heading == 90);
  CHECK(back.detections[0].footprint.size() == 4);
  REQUIRE(back.rejected.size() == 1);
  CHECK(back.rejected[0].reason == "none");
  const Json geo = Json::parse(documents::serialize_detections_geojson(r));
  CHECK(geo["crs"]["properties"]["name"] == "urn:ogc:def:crs:EPSG::32633");
  const Json& ring = geo["features"][0]["geometry"]["coordinates"][0];
  CHECK(ring.size() == 5);
  CHECK(ring[0] == ring[4]);
  CHECK(documents::open_ground_density(r.density) == 100.0);
  CHECK(std::string(documents::open_ground_density_key(r.density)) == "ground");
  // Without the open ground's density: all returns', named as such; neither: none.
  CHECK(std::string(documents::open_ground_density_key(Json{{"all", 31.0}, {"ground", nullptr}})) == "all");
  CHECK(documents::open_ground_density(Json{{"all", 31.0}, {"ground", nullptr}}) == 31.0);
  CHECK(documents::open_ground_density_key(Json{{"first", 3.0}}) == nullptr);
  CHECK_FALSE(documents::open_ground_density(Json::array()).has_value());
  r.detections[0].footprint[1][0] = std::nan("");
  CHECK_THROWS_WITH(documents::serialize_detections(r),
                    Catch::Contains("collect: refusing to write a non-finite number"));
}

TEST_CASE("detections writer: crs_from follows crs when given, in both files; absent otherwise") {
  documents::DetectionsRecord r;
  r.provenance = {"collect", "9.9", {}, {"idx.json"}};
  r.index = "idx.json";
  r.tile = "tile.laz";
  r.crs = "EPSG:2154";
  r.crs_from = "tile: LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154";
  const std::string text = documents::serialize_detections(r);
  CHECK(text.find(" \"crs\": \"EPSG:2154\",\n \"crs_from\": \"tile: LASF_Projection 2112 (OGC WKT): PROJCS "
                  "AUTHORITY EPSG 2154\",\n \"candidates\": 0,") != std::string::npos);
  const std::string geo = documents::serialize_detections_geojson(r);
  CHECK(geo.find(
            "   \"name\": \"urn:ogc:def:crs:EPSG::2154\"\n  }\n },\n \"crs_from\": \"tile: LASF_Projection "
            "2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154\",\n \"features\": []") != std::string::npos);
  r.crs_from.clear();
  CHECK(documents::serialize_detections(r).find("crs_from") == std::string::npos);
  CHECK(documents::serialize_detections_geojson(r).find("crs_from") == std::string::npos);
  r.crs.clear();
  r.crs_from = "--crs";  // no CRS: no crs member in the GeoJSON, so no crs_from either
  CHECK(documents::serialize_detections_geojson(r).find("crs") == std::string::npos);
}
