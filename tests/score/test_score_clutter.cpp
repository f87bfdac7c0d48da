// score's false alarms by clutter kind (issue 29): a hand-made truth with clutter and
// detections on it, on terrain and on a vehicle, against the hand-computed table.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <utility>

#include "canopy/documents/scene_score.h"
#include "score/clutter.h"
#include "score/score.h"

using namespace canopy;
using Json = nlohmann::ordered_json;

namespace {

const double E = 500000, N = 5400000;

Json clutter(const char* kind, double x, double y, double l, double w, double heading) {
  return Json{
      {"kind", kind},
      {"box",
       {{"centre", {E + x, N + y, 101}}, {"size", {l, w, 2}}, {"heading", heading}, {"pitch", 0}, {"roll", 0}}}};
}

// A 30 x 30 m tile (0.09 ha): a sedan at (10, 10); a caravan 6 x 2.4 m at (20, 5) heading 90
// (its box x 18.8 - 21.2, y 2 - 8), a rock 4 x 2 m at (5, 25), a boulder 1.5 x 1.2 m at (25, 25),
// a tent 4 x 3 m at (15, 20).
std::string truth_text() {
  Json j{{"format", "canopy.scene_truth"},
         {"version", 1},
         {"extent", {30, 30}},
         {"vehicles", Json::array({{{"instance", 1},
                                    {"model", "sedan"},
                                    {"pose", {{"x", E + 10}, {"y", N + 10}, {"z", 100}, {"heading", 30}}},
                                    {"canopy_cover", 0.1}}})},
         {"clutter", Json::array({clutter("caravan", 20, 5, 6, 2.4, 90), clutter("rock", 5, 25, 4, 2, 0),
                                  clutter("boulder", 25, 25, 1.5, 1.2, 0), clutter("tent", 15, 20, 4, 3, 0)})}};
  return j.dump();
}

Json det(const std::string& id, const char* model, double x, double y) {
  return Json{{"candidate", id},
              {"level", "model"},
              {"model", model},
              {"confidence", 0.9},
              {"pose", {{"x", E + x}, {"y", N + y}, {"z", 100}, {"heading", 0}, {"pitch", 0}, {"roll", 0}}}};
}

std::string detections_text() {
  Json cls = det("c4", "", 26.0, 25.5);
  cls["level"] = "class";
  cls["model"] = nullptr;
  cls["class"] = "car";
  cls["group"] = "car";
  cls["heading_ambiguity_deg"] = 180;
  const Json dets = Json::array({
      det("c1", "sedan", 10, 10),    // the sedan: matched
      det("c2", "semi", 20.5, 7.5),  // inside the caravan's box (outside it were the heading ignored)
      det("c3", "tank", 6.4, 25.2),  // inside the rock's box
      cls,                           // class level, 1.12 m from the boulder's centre, outside its box
      det("c5", "obj1", 2, 12),      // on the terrain
      det("c6", "tank", 5.5, 24.5),  // the rock again
  });
  return Json{
      {"format", "canopy.detections"}, {"version", 2}, {"candidates", 6}, {"none", 0}, {"detections", dets}}
      .dump();
}

const Json& row(const Json& table, const std::string& cover, const std::string& kind) {
  for (const Json& r : table) {
    if (r["cover"] == cover && r["kind"] == kind) return r;
  }
  FAIL("no row " << cover << " " << kind);
  static const Json none;
  return none;
}

}  // namespace

TEST_CASE("clutter: a false alarm is put on the object whose box holds it, else whose centre is near") {
  const score::Truth t = score::parse_truth(truth_text(), "truth.json");
  REQUIRE(t.clutter.size() == 4);
  CHECK(t.clutter[0].kind == "caravan");
  CHECK(t.clutter[0].length == 6);
  CHECK(t.clutter[0].heading == 90);
  CHECK(score::clutter_at(t, E + 20.5, N + 7.5, 1.5) == 0);   // in the box, 2.55 m from the centre
  CHECK(score::clutter_at(t, E + 22.5, N + 5, 1.5) == -1);    // along the caravan's width: outside
  CHECK(score::clutter_at(t, E + 26.0, N + 25.5, 1.5) == 2);  // 1.12 m from the boulder's centre
  CHECK(score::clutter_at(t, E + 26.0, N + 25.5, 1.0) == -1);
  CHECK(score::clutter_at(t, E + 2, N + 12, 1.5) == -1);
}

TEST_CASE("clutter: false alarms by kind, per hectare and the share of objects answered, with intervals") {
  score::Tile tile;
  tile.truth = score::parse_truth(truth_text(), "truth.json");
  tile.detections = score::parse_detections(detections_text(), "detections.json");
  tile.cover = "light";
  const documents::SceneScore s = score::score({tile}, score::Params{});
  const Json doc = Json::parse(documents::write_scene_score(s, {}));
  const Json& table = doc["clutter"];
  // all and light: boulder, caravan, rock, tent (name order), none.
  REQUIRE(table.size() == 10);
  CHECK(table[0]["kind"] == "boulder");
  CHECK(table[4]["kind"] == "none");
  CHECK(table[5]["cover"] == "light");
  const double ha = 0.09;

  const Json& rock = row(table, "all", "rock");
  CHECK(rock["objects"] == 1);
  CHECK(rock["objects_distinct"] == 1);
  CHECK(rock["false_alarms"] == 2);
  CHECK(rock["model_level"] == 2);
  CHECK(rock["class_level"] == 0);
  CHECK(rock["area_ha"].get<double>() == Approx(ha));
  CHECK(rock["false_alarms_per_ha"].get<double>() == Approx(2 / ha));
  // One render: no bootstrap; exact Poisson for 2: [0.2422, 7.2247] / 0.09 ha.
  CHECK(rock["false_alarms_per_ha_lo"].get<double>() == Approx(0.24220 / ha).epsilon(1e-3));
  CHECK(rock["false_alarms_per_ha_hi"].get<double>() == Approx(7.22470 / ha).epsilon(1e-3));
  CHECK(rock["answered"] == 1);
  CHECK(rock["answered_share"].get<double>() == Approx(1));
  CHECK(rock["answered_share_lo"].get<double>() == Approx(0.2065).margin(1e-4));  // Wilson 1/1
  CHECK(rock["answered_share_hi"].get<double>() == Approx(1));

  const Json& caravan = row(table, "all", "caravan");
  CHECK(caravan["false_alarms"] == 1);
  CHECK(caravan["false_alarms_per_ha_lo"].get<double>() == Approx(0.025318 / ha).epsilon(1e-3));
  CHECK(caravan["false_alarms_per_ha_hi"].get<double>() == Approx(5.5716 / ha).epsilon(1e-3));

  const Json& boulder = row(table, "all", "boulder");
  CHECK(boulder["false_alarms"] == 1);
  CHECK(boulder["model_level"] == 0);
  CHECK(boulder["class_level"] == 1);

  const Json& tent = row(table, "all", "tent");
  CHECK(tent["objects"] == 1);
  CHECK(tent["false_alarms"] == 0);
  CHECK(tent["false_alarms_per_ha"].get<double>() == Approx(0));
  CHECK(tent["false_alarms_per_ha_hi"].get<double>() == Approx(3.6889 / ha).epsilon(1e-3));
  CHECK(tent["answered"] == 0);
  CHECK(tent["answered_share_lo"].get<double>() == Approx(0));
  CHECK(tent["answered_share_hi"].get<double>() == Approx(0.7935).margin(1e-4));  // Wilson 0/1

  const Json& none = row(table, "all", "none");
  CHECK(none["false_alarms"] == 1);
  CHECK(none["objects"].is_null());
  CHECK(none["answered_share"].is_null());
  CHECK(none["answered_share_lo"].is_null());

  // Every false alarm once: the table adds up to the summary's fp + class_fp.
  int sum = 0;
  for (int k = 0; k < 5; ++k) sum += table[k]["false_alarms"].get<int>();
  const Json& all = doc["summary"][0];
  CHECK(sum == all["fp"].get<int>() + all["class_fp"].get<int>());
  CHECK(sum == 5);
  CHECK(row(table, "light", "rock")["false_alarms"] == 2);

  // The table survives the reader (report reads it back) and its CSV.
  const documents::SceneScore back =
      documents::read_scene_score(documents::write_scene_score(s, {}), "s.json");
  CHECK(back.clutter.size() == 10);
  CHECK_THAT(documents::scene_score_csv(s, "clutter"),
             Catch::StartsWith("cover,kind,tiles,renders,area_ha,objects"));
}

TEST_CASE("clutter: tiles without clutter in their truth give the none row alone") {
  Json t = Json::parse(truth_text());
  t.erase("clutter");
  score::Tile tile;
  tile.truth = score::parse_truth(t.dump(), "truth.json");
  tile.detections = score::parse_detections(detections_text(), "detections.json");
  const Json doc = Json::parse(documents::write_scene_score(score::score({tile}, score::Params{}), {}));
  REQUIRE(doc["clutter"].size() == 1);
  CHECK(doc["clutter"][0]["kind"] == "none");
  CHECK(doc["clutter"][0]["false_alarms"] == 5);
  // A malformed clutter object names itself.
  t = Json::parse(truth_text());
  t["clutter"][1]["box"].erase("size");
  CHECK_THROWS_WITH(score::parse_truth(t.dump(), "truth.json"),
                    Catch::Contains("truth.json") && Catch::Contains("clutter[1].box"));
}

TEST_CASE(
    "clutter: a false alarm inside a true vehicle's footprint is put on the vehicle, before any clutter") {
  // The sedan at (10, 10) heading 30 gets its footprint: 4.6 x 1.8 m. A detection 2.0 m ahead of
  // its centre along its axis (beyond the 1.5 m match radius, inside the 2.3 m half-length), a
  // second answer on its centre (the first took the match), and one 2.5 m ahead (outside).
  Json t = Json::parse(truth_text());
  const double h = 30 * 3.14159265358979 / 180, c = std::cos(h), s = std::sin(h);
  Json corners = Json::array();
  for (auto [a, b] : {std::pair{2.3, 0.9}, {-2.3, 0.9}, {-2.3, -0.9}, {2.3, -0.9}})
    corners.push_back({E + 10 + a * c - b * s, N + 10 + a * s + b * c});
  t["vehicles"][0]["footprint"] = corners;
  // A tent whose box overlaps the sedan's front: the vehicle comes first.
  t["clutter"][3] = clutter("tent", 10 + 2.0 * c, 10 + 2.0 * s, 1, 1, 0);
  score::Tile tile;
  tile.truth = score::parse_truth(t.dump(), "truth.json");
  REQUIRE(tile.truth.vehicles[0].footprint.size() == 4);
  CHECK(score::vehicle_at(tile.truth, E + 10 + 2.0 * c, N + 10 + 2.0 * s) == 0);
  CHECK(score::vehicle_at(tile.truth, E + 10 + 2.5 * c, N + 10 + 2.5 * s) == -1);
  CHECK(score::vehicle_at(tile.truth, E + 10 - 1.0 * s, N + 10 + 1.0 * c) == -1);  // 1.0 m to its side
  CHECK(score::vehicle_at(tile.truth, E + 10 - 0.8 * s, N + 10 + 0.8 * c) == 0);

  const Json dets = Json::array({det("c1", "sedan", 10, 10), det("c2", "sedan", 10, 10),
                                 det("c3", "sedan", 10 + 2.0 * c, 10 + 2.0 * s),
                                 det("c4", "sedan", 10 + 2.5 * c, 10 + 2.5 * s), det("c5", "obj1", 2, 12)});
  tile.detections = score::parse_detections(
      Json{{"format", "canopy.detections"}, {"version", 2}, {"candidates", 5}, {"none", 0}, {"detections", dets}}
          .dump(),
      "detections.json");
  const Json doc = Json::parse(documents::write_scene_score(score::score({tile}, score::Params{}), {}));
  const Json& table = doc["clutter"];
  // One cover ("all"): boulder, caravan, rock, tent, vehicle, none.
  REQUIRE(table.size() == 6);
  CHECK(table[4]["kind"] == "vehicle");
  CHECK(table[5]["kind"] == "none");
  const Json& vehicle = row(table, "all", "vehicle");
  CHECK(vehicle["false_alarms"] == 2);  // the second answer and the one 2.0 m ahead
  CHECK(vehicle["objects"] == 1);
  CHECK(vehicle["answered"] == 1);
  CHECK(row(table, "all", "tent")["false_alarms"] == 1);  // 2.5 m ahead: outside the sedan, 0.5 m from the tent
  CHECK(row(table, "all", "none")["false_alarms"] == 1);  // the terrain
  CHECK(doc["summary"][0]["fp"] == 4);
}
