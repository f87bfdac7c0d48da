// documents/scene_score.h: score.json (canopy.scene_score v1) as score writes it, with its CSV
// tables, and as report and topview read it.
#include <catch2/catch.hpp>

#include <string>

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/documents/scene_score.h"

using namespace canopy;
using Json = nlohmann::ordered_json;

namespace {

// One tile: a right detection, a false alarm and a missed vehicle (hand-built).
documents::SceneScore example() {
  documents::SceneScore s;
  s.has_params = true;
  s.params.match_radius_m = 1.5;
  s.params.cover_bins = {0, 0.5, 1};
  s.params.flip_threshold_deg = 90;
  documents::ScoreTile t;
  t.detections = "d.json";
  t.truth = "t.json";
  t.noise_mm = 0.0;
  t.area_ha = 0.09;
  t.true_count = 2;
  t.tp = 1;
  t.fp = 1;
  t.fn = 1;
  t.class_detections = 0;
  t.class_tp = 0;
  t.class_fp = 0;
  t.fn_any_level = 1;
  s.tiles = {t};
  s.summary = {{{"cover", "all"},
                {"noise_mm", "all"},
                {"tiles", 1},
                {"area_ha", 0.09},
                {"tp", 1},
                {"precision", 0.5},
                {"f1", documents::ScoreValue()},
                {"label", "a,\"b\""}}};
  s.pr = {{{"threshold", 0.9}, {"detections", 1}, {"precision", 1.0}}};
  documents::ScoreMatch right;
  right.tile = 0;
  right.candidate = "c1";
  right.level = "model";
  right.model = "sedan";
  right.confidence = 0.9;
  right.x = 10.5;
  right.y = 10;
  right.heading = 31;
  right.outcome = "right";
  right.instance = 1;
  right.true_model = "sedan";
  right.cover = 0.25;
  right.distance_m = 0.5;
  right.heading_error_deg = 1;
  documents::ScoreMatch alarm = right;
  alarm.candidate = "c2";
  alarm.confidence = 0.4;
  alarm.outcome = "false_alarm";
  alarm.instance.reset();
  alarm.true_model.reset();
  alarm.cover.reset();
  alarm.distance_m.reset();
  alarm.heading_error_deg.reset();
  documents::ScoreMatch missed;
  missed.tile = 0;
  missed.x = 20;
  missed.y = 20;
  missed.heading = 90;
  missed.outcome = "missed";
  missed.instance = 2;
  missed.true_model = "tank";
  missed.cover = 0.75;
  s.matches = {right, alarm, missed};
  return s;
}

std::string refusal(const Json& doc) {
  try {
    documents::read_scene_score(doc.dump(), "s.json");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "s.json");
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("scene score: the writer's members, types and order") {
  const std::string text = documents::write_scene_score(example(), {"score", "9.9", {}, {"d.json", "t.json"}});
  CHECK(text.back() == '\n');
  CHECK(text.rfind("{\n \"format\": \"canopy.scene_score\",\n \"version\": 1,\n \"provenance\": {", 0) == 0);
  const Json j = Json::parse(text);
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.push_back(k);
  CHECK(keys == std::vector<std::string>{"format", "version", "provenance", "params", "tiles", "summary",
                                         "pr", "models", "cover_bins", "reliability", "clutter", "matches"});
  CHECK(j["params"].dump() == R"({"match_radius_m":1.5,"cover_bins":[0.0,0.5,1.0],"flip_threshold_deg":90.0})");
  CHECK(j["tiles"][0].dump() ==
        R"({"detections":"d.json","truth":"t.json","cover":null,"noise_mm":0.0,"area_ha":0.09,"true":2,"tp":1,)"
        R"("fp":1,"fn":1,"class_detections":0,"class_tp":0,"class_fp":0,"fn_any_level":1})");
  CHECK(j["summary"][0].dump() ==
        R"({"cover":"all","noise_mm":"all","tiles":1,"area_ha":0.09,"tp":1,"precision":0.5,"f1":null,"label":"a,\"b\""})");
  CHECK(j["matches"][1].dump() ==
        R"({"tile":0,"candidate":"c2","level":"model","model":"sedan","class":null,"confidence":0.4,"x":10.5,)"
        R"("y":10.0,"heading":31.0,"outcome":"false_alarm","instance":null,"true_model":null,"cover":null,)"
        R"("distance_m":null,"heading_error_deg":null,"fate":null,"fate_candidate":null,"fate_reason":null,)"
        R"("fate_density":null})");
  CHECK(j["models"] == Json::array());
}

TEST_CASE("scene score: CSV tables") {
  const documents::SceneScore s = example();
  CHECK(documents::scene_score_csv(s, "summary") ==
        "cover,noise_mm,tiles,area_ha,tp,precision,f1,label\nall,all,1,0.09,1,0.5,,\"a,\"\"b\"\"\"\n");
  CHECK(documents::scene_score_csv(s, "models").empty());
  const std::string m = documents::scene_score_csv(s, "matches");
  CHECK(
      m.substr(0, m.find('\n')) ==
      "tile,candidate,level,model,class,confidence,x,y,heading,outcome,instance,true_model,cover,distance_m,"
      "heading_error_deg,fate,fate_candidate,fate_reason,fate_density");
  CHECK(m.find("\n0,,,,,,20,20,90,missed,2,tank,0.75,,,,,,\n") != std::string::npos);
  CHECK_THROWS_WITH(documents::scene_score_csv(s, "other"), Catch::Contains("no table \"other\""));
}

TEST_CASE("scene score: what score writes reads back") {
  const std::string text = documents::write_scene_score(example(), {});
  const documents::SceneScore s = documents::read_scene_score(text, "s.json");
  REQUIRE(s.has_params);
  CHECK(s.params.match_radius_m == 1.5);
  CHECK(s.params.cover_bins == std::vector<double>{0, 0.5, 1});
  REQUIRE(s.tiles.size() == 1);
  CHECK(s.tiles[0].area_ha == 0.09);
  CHECK(s.tiles[0].true_count == 2);
  CHECK_FALSE(s.tiles[0].cover);
  REQUIRE(s.matches.size() == 3);
  CHECK(s.matches[0].instance == 1);
  CHECK(s.matches[1].candidate == std::string("c2"));
  CHECK_FALSE(s.matches[1].instance);
  CHECK_FALSE(s.matches[2].candidate);
  CHECK(s.matches[2].x == 20.0);
  REQUIRE(s.summary.size() == 1);
  const documents::ScoreValue* tiles = documents::score_cell(s.summary[0], "tiles");
  REQUIRE(tiles);
  CHECK(tiles->kind == documents::ScoreValue::Kind::integer);
  CHECK(documents::score_cell(s.summary[0], "area_ha")->number == 0.09);
  CHECK(documents::score_cell(s.summary[0], "f1")->kind == documents::ScoreValue::Kind::null);
  CHECK_FALSE(documents::score_cell(s.summary[0], "none"));
  // Written again from what was read: the same text.
  CHECK(documents::write_scene_score(s, {}) == text);
}

TEST_CASE("scene score: the provenance's text parameters read back, others left out") {
  const std::string text = documents::write_scene_score(
      example(), {"score", "9.9", {{"csv", "results/scenes/summary.csv"}, {"match-radius", "1.5"}}, {}});
  const documents::SceneScore s = documents::read_scene_score(text, "s.json");
  CHECK(s.parameters == std::vector<std::pair<std::string, std::string>>{
                            {"csv", "results/scenes/summary.csv"}, {"match-radius", "1.5"}});
  Json j = Json::parse(text);
  j["provenance"]["parameters"] = Json{{"seed", 3}, {"csv", "a/b.csv"}, {"none", nullptr}};
  CHECK(documents::read_scene_score(j.dump(), "s.json").parameters ==
        std::vector<std::pair<std::string, std::string>>{{"csv", "a/b.csv"}});
  j.erase("provenance");
  CHECK(documents::read_scene_score(j.dump(), "s.json").parameters.empty());
}

TEST_CASE("scene score: refusals name the file and the problem") {
  const Json good = Json::parse(documents::write_scene_score(example(), {}));
  CHECK(refusal(good).empty());
  auto with = [&](auto edit) {
    Json j = good;
    edit(j);
    return refusal(j);
  };
  CHECK_THAT(with([](Json& j) { j["format"] = "canopy.scene_truth"; }),
             Catch::Contains("canopy.scene_score"));
  CHECK_THAT(with([](Json& j) { j["version"] = 2; }), Catch::Contains("version 2"));
  CHECK_THAT(with([](Json& j) { j.erase("matches"); }), Catch::Contains("score: missing \"matches\""));
  CHECK_THAT(with([](Json& j) { j["tiles"] = Json::object(); }),
             Catch::Contains("score.tiles must be an array"));
  CHECK_THAT(with([](Json& j) { j["tiles"][0] = 3; }), Catch::Contains("tiles[0] must be an object"));
  CHECK_THAT(with([](Json& j) { j["tiles"][0]["area_ha"] = -1; }),
             Catch::Contains("tiles[0].area_ha must be >= 0"));
  CHECK_THAT(with([](Json& j) { j["tiles"][0]["tp"] = 1.5; }),
             Catch::Contains("tiles[0].tp must be a non-negative integer"));
  CHECK_THAT(with([](Json& j) { j["params"]["match_radius_m"] = 0; }),
             Catch::Contains("params.match_radius_m must be > 0"));
  CHECK_THAT(with([](Json& j) { j["params"]["cover_bins"][1] = "x"; }),
             Catch::Contains("params.cover_bins[1] must be a finite number"));
  CHECK_THAT(with([](Json& j) { j["matches"][0]["tile"] = 1; }),
             Catch::Contains("matches[0].tile 1 is not one of the 1 tiles"));
  CHECK_THAT(with([](Json& j) { j["matches"][0]["tile"] = -1; }),
             Catch::Contains("matches[0].tile must be a non-negative integer"));
  CHECK_THAT(
      with([](Json& j) { j["matches"][0]["outcome"] = "maybe"; }),
      Catch::Contains("matches[0].outcome must be right, wrong, false_alarm or missed, not \"maybe\""));
  CHECK_THAT(with([](Json& j) { j["matches"][0].erase("outcome"); }),
             Catch::Contains("matches[0]: missing \"outcome\""));
  CHECK_THAT(with([](Json& j) { j["matches"][1]["candidate"] = nullptr; }),
             Catch::Contains("matches[1]: missing \"candidate\""));
  CHECK_THAT(with([](Json& j) { j["matches"][1]["candidate"] = "c1"; }),
             Catch::Contains("matches[1].candidate \"c1\" has a second outcome in tile 0"));
  CHECK_THAT(with([](Json& j) { j["matches"][2]["instance"] = nullptr; }),
             Catch::Contains("matches[2]: missing \"instance\""));
  CHECK_THAT(with([](Json& j) { j["matches"][0].erase("instance"); }),
             Catch::Contains("matches[0]: missing \"instance\""));
  CHECK_THAT(with([](Json& j) { j["matches"][0]["x"] = "10"; }),
             Catch::Contains("matches[0].x must be a finite number"));
  CHECK_THAT(with([](Json& j) { j["matches"][0]["true_model"] = 3; }),
             Catch::Contains("matches[0].true_model must be a string"));
  CHECK_THAT(with([](Json& j) { j["summary"][0]["tp"] = Json::array(); }),
             Catch::Contains("summary[0].tp must be a number, a text or null, not an array"));
  CHECK_THAT(with([](Json& j) { j["pr"] = 5; }), Catch::Contains("score.pr must be an array"));
  CHECK_THAT(refusal(Json::parse("[1]")), Catch::Contains("s.json"));
  // A hand-written score (topview's and report's tests): tiles of empty objects, no params, no x, y.
  const Json minimal = Json::parse(
      R"({"format":"canopy.scene_score","version":1,"tiles":[{}],"matches":[{"tile":0,"candidate":"c1",)"
      R"("outcome":"wrong","instance":1},{"tile":0,"candidate":null,"outcome":"missed","instance":2}]})");
  CHECK(refusal(minimal).empty());
  const documents::SceneScore m = documents::read_scene_score(minimal.dump(), "m.json");
  CHECK_FALSE(m.has_params);
  CHECK_FALSE(m.tiles[0].area_ha);
  // ... which the writer refuses: a tile without its counts is a writer's bug.
  CHECK_THROWS_WITH(documents::write_scene_score(m, {}), Catch::Contains("refusing to write"));
}
