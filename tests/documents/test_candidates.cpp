// documents/candidates.h: detect's index.json (canopy.candidates v2; v1 read too), read by
// collect, classify, topview, candtruth and report through one reader. A hand-written index in detect's exact layout reads
// to the values it holds and writes back byte for byte; malformed ones are refused naming the
// file and the member.
#include <catch2/catch.hpp>

#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/documents/candidates.h"

using namespace canopy;

namespace {

// As detect writes it (one-space indent): two candidates, no ground truth (issue 30).
const std::string kIndex = R"({
 "format": "canopy.candidates",
 "version": 2,
 "provenance": {
  "tool": "detect",
  "version": "0.1.0",
  "parameters": {
   "cell": "0.5"
  },
  "inputs": [
   "tile.pcd"
  ]
 },
 "tile": "tile.pcd",
 "tile_points": 9883,
 "origin": [
  500000.0,
  4400000.0,
  180.0
 ],
 "classes": "classes.ply",
 "ground": {
  "cell": 0.5,
  "cells": 400,
  "ground_cells": 390,
  "filled_cells": 10,
  "ground_points": 8611
 },
 "density": {
  "all": 98.5,
  "ground": null,
  "first": null,
  "cell": 1.0,
  "occupied_cells": 100,
  "open_ground_cells": 91
 },
 "margin": 0.5,
 "candidates": [
  {
   "id": "c0001",
   "file": "c0001.pcd",
   "transform": [
    [
     0.6,
     -0.8,
     0.0,
     500012.25
    ],
    [
     0.8,
     0.6,
     0.0,
     4399987.5
    ],
    [
     0.0,
     0.0,
     1.0,
     181.5
    ],
    [
     0.0,
     0.0,
     0.0,
     1.0
    ]
   ],
   "centre": [
    500012.25,
    4399987.5,
    181.5
   ],
   "length": 4.5,
   "width": 1.75,
   "heading": 0.9272952180016122,
   "height": 1.5,
   "point_count": 1421,
   "object_points": 501,
   "density": 63.6,
   "planarity": 0.74,
   "planar_area": 9.3
  },
  {
   "id": "c0002",
   "file": "c0002.pcd",
   "transform": [
    [
     1.0,
     0.0,
     0.0,
     500020.0
    ],
    [
     0.0,
     1.0,
     0.0,
     4399990.0
    ],
    [
     0.0,
     0.0,
     1.0,
     180.0
    ],
    [
     0.0,
     0.0,
     0.0,
     1.0
    ]
   ],
   "centre": [
    500020.0,
    4399990.0,
    180.0
   ],
   "length": 3.0,
   "width": 2.0,
   "heading": 0.0,
   "height": 1.0,
   "point_count": 300,
   "object_points": 120,
   "density": 20.0,
   "planarity": 0.1,
   "planar_area": 0.5
  }
 ]
}
)";

// A version 1 index: no margin, ground truth per candidate and per vehicle.
nlohmann::ordered_json version1() {
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(kIndex);
  j["version"] = 1;
  j.erase("margin");
  j["candidates"][0]["truth"] = {{"instance", 7}, {"points", 512}, {"coverage", 1.0}, {"purity", 0.99}};
  j["candidates"][1]["truth"] = nullptr;
  j["instances"] =
      nlohmann::ordered_json::parse(R"([{"instance": 7, "points": 512, "candidates": ["c0001"]}])");
  return j;
}

formats::Provenance provenance() { return {"detect", "0.1.0", {{"cell", "0.5"}}, {"tile.pcd"}}; }

// The message read_candidates throws for `doc`, "" when it reads it.
std::string refusal(const nlohmann::ordered_json& doc) {
  try {
    documents::read_candidates(doc.dump(), "cands/index.json");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "cands/index.json");
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("candidates: a hand-written index reads to its values and writes back byte for byte") {
  const documents::Candidates d = documents::read_candidates(kIndex, "index.json");
  CHECK(d.tile == "tile.pcd");
  CHECK(d.tile_points == 9883);
  CHECK(d.classes == "classes.ply");
  REQUIRE(d.ground);
  CHECK(d.ground->cell == 0.5);
  CHECK(d.ground->cells == 400);
  CHECK(d.ground->ground_points == 8611);
  CHECK(d.density_all() == 98.5);
  CHECK_FALSE(d.density_ground());  // null: too little open ground in the tile
  REQUIRE(d.candidates.size() == 2);
  const documents::Candidate& c = d.candidates[0];
  CHECK(c.id == "c0001");
  CHECK(c.transform[1] == -0.8);
  CHECK(c.transform[3] == 500012.25);
  CHECK(c.transform[11] == 181.5);
  CHECK(c.length == 4.5);
  CHECK(c.width == 1.75);
  CHECK(c.object_points == 501);
  CHECK(c.object_density() == 63.6);
  CHECK(d.margin == 0.5);
  CHECK(d.find("c0002") == &d.candidates[1]);
  CHECK(d.find("c0003") == nullptr);
  CHECK(documents::write_candidates(d, provenance()) == kIndex);
}

TEST_CASE("candidates: the tile's CRS, written after tile_points only when the tile records one") {
  documents::Candidates d = documents::read_candidates(kIndex, "index.json");
  CHECK(d.crs.empty());
  CHECK(d.crs_from.empty());
  d.crs = "EPSG:2154";
  d.crs_from = "LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154";
  const std::string text = documents::write_candidates(d, provenance());
  const std::string members =
      " \"tile_points\": 9883,\n \"crs\": \"EPSG:2154\",\n"
      " \"crs_from\": \"LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154\",\n \"origin\": [";
  CHECK(text.find(members) != std::string::npos);
  const documents::Candidates back = documents::read_candidates(text, "index.json");
  CHECK(back.crs == "EPSG:2154");
  CHECK(back.crs_from == d.crs_from);
  CHECK(documents::write_candidates(back, provenance()) == text);
  // Without a CRS: the index as before, byte for byte.
  d.crs.clear();
  CHECK(documents::write_candidates(d, provenance()) == kIndex);
}

TEST_CASE("candidates: a version 1 index reads, its ground truth dropped unread") {
  const documents::Candidates d = documents::read_candidates(version1().dump(1), "old/index.json");
  REQUIRE(d.candidates.size() == 2);
  CHECK(d.candidates[0].id == "c0001");
  CHECK(d.candidates[0].object_points == 501);
  CHECK_FALSE(d.margin);
  // Written again it is a version 2 index, once it has a margin.
  CHECK_THROWS_WITH(documents::write_candidates(d, provenance()), Catch::Contains("margin"));
  documents::Candidates m = d;
  m.margin = 0.5;
  CHECK(documents::write_candidates(m, provenance()) == kIndex);
}

TEST_CASE("candidates: a candidate's density is its own, else object points over its footprint") {
  documents::Candidate c;
  c.length = 4;
  c.width = 2;
  CHECK_FALSE(c.object_density());
  c.object_points = 400;
  CHECK(c.object_density() == 50.0);
  c.density = 30.0;
  CHECK(c.object_density() == 30.0);
}

TEST_CASE("candidates: refusals name the file and the problem") {
  using Json = nlohmann::ordered_json;
  const Json good = Json::parse(kIndex);
  CHECK(refusal(good).empty());
  Json other = good, version = good, no_list = good, no_width = good, text_width = good, bad_id = good,
       twice = good, skew = good, mirror = good, count = good, truth = good, instances = good, margin = good,
       old_truth = version1();
  other["format"] = "canopy.detections";
  version["version"] = 3;
  truth["candidates"][0]["truth"] = nullptr;
  instances["instances"] = nlohmann::ordered_json::array();
  margin["margin"] = -0.5;
  old_truth["candidates"][0]["truth"].erase("purity");
  no_list.erase("candidates");
  no_width["candidates"][0].erase("width");
  text_width["candidates"][1]["width"] = "2";
  bad_id["candidates"][0]["id"] = "../c1";
  twice["candidates"][1]["id"] = "c0001";
  skew["candidates"][0]["transform"][0][0] = 0.7;
  mirror["candidates"][1]["transform"][0][0] = -1.0;
  count["tile_points"] = 9.5;
  Json ground = good, text_ground = good, open = good;
  ground["density"]["ground"] = -1.0;
  text_ground["density"]["ground"] = "8";
  open["density"]["ground"] = 8.5;
  CHECK_THAT(refusal(ground), Catch::Contains("density.ground must be >= 0 or null"));
  CHECK_THAT(refusal(text_ground), Catch::Contains("density.ground must be a finite number"));
  CHECK(refusal(open).empty());
  CHECK(documents::read_candidates(open.dump(), "index.json").density_ground() == 8.5);
  // density.first likewise (classify --fill-tile-first): a number >= 0 or null; 0 or null is none.
  Json first = good, text_first = good, null_first = good, zero_first = good;
  first["density"]["first"] = -0.5;
  text_first["density"]["first"] = "9";
  null_first["density"]["first"] = nullptr;
  zero_first["density"]["first"] = 0.0;
  open["density"]["first"] = 9.25;
  CHECK_THAT(refusal(first), Catch::Contains("density.first must be >= 0 or null"));
  CHECK_THAT(refusal(text_first), Catch::Contains("density.first must be a finite number"));
  CHECK(refusal(null_first).empty());
  CHECK_FALSE(documents::read_candidates(null_first.dump(), "index.json").density_first());
  CHECK_FALSE(documents::read_candidates(zero_first.dump(), "index.json").density_first());
  CHECK(documents::read_candidates(open.dump(), "index.json").density_first() == 9.25);
  CHECK_THAT(refusal(other), Catch::Contains("canopy.detections"));
  CHECK_THAT(refusal(version), Catch::Contains("version 3"));
  CHECK_THAT(refusal(no_list), Catch::Contains("missing \"candidates\""));
  CHECK_THAT(refusal(no_width), Catch::Contains("candidates[0]: missing \"width\""));
  CHECK_THAT(refusal(text_width), Catch::Contains("candidates[1].width must be a finite number, not \"2\""));
  CHECK_THAT(refusal(bad_id), Catch::Contains("not a plain name"));
  CHECK_THAT(refusal(twice), Catch::Contains("candidates[1].id \"c0001\" repeats"));
  CHECK_THAT(refusal(skew), Catch::Contains("candidates[0].transform: the 3 x 3 part is not a rotation"));
  CHECK_THAT(refusal(mirror), Catch::Contains("candidates[1].transform: the 3 x 3 part is a reflection"));
  CHECK_THAT(refusal(count), Catch::Contains("tile_points must be a non-negative integer, not 9.5"));
  // Ground truth in a version 2 index is refused, even null: it belongs to candtruth's file.
  CHECK_THAT(refusal(truth), Catch::Contains("candidates[0].truth: a version 2 index holds no ground truth"));
  CHECK_THAT(refusal(instances), Catch::Contains("instances: a version 2 index holds no ground truth"));
  CHECK_THAT(refusal(margin), Catch::Contains("margin must be >= 0"));
  Json crs = good;
  crs["crs"] = "Lambert-93";
  CHECK_THAT(refusal(crs), Catch::Contains("crs must be EPSG:<code>"));
  // No code 0 and no leading zeros (one spelling per code: the --crs comparison is textual).
  crs["crs"] = "EPSG:0";
  CHECK_THAT(refusal(crs), Catch::Contains("crs must be EPSG:<code>"));
  crs["crs"] = "EPSG:02154";
  CHECK_THAT(refusal(crs), Catch::Contains("crs must be EPSG:<code>"));
  crs["crs"] = 2154;
  CHECK_THAT(refusal(crs), Catch::Contains("crs"));
  // A version 1 index's truth is not read at all, so not checked either.
  CHECK(refusal(old_truth).empty());
  CHECK_THROWS_AS(documents::read_candidates("{\"format\": \"canopy.candidates\"", "x.json"),
                  common::DataError);
}

TEST_CASE("candidates: the writer refuses a non-finite number and a candidate detect did not fill") {
  documents::Candidates d = documents::read_candidates(kIndex, "index.json");
  d.candidates[0].length = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(documents::write_candidates(d, provenance()), Catch::Contains("non-finite"));
  d = documents::read_candidates(kIndex, "index.json");
  d.candidates[1].heading.reset();
  CHECK_THROWS_WITH(documents::write_candidates(d, provenance()), Catch::Contains("heading"));
}
