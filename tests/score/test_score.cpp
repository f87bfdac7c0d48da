// score: precision, recall and the rest against hand-computed answers on hand-written tiles.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "canopy/common/error.h"
#include "canopy/documents/model_classes.h"
#include "score/score.h"
#include "support/cli.h"

using namespace canopy;
using Json = nlohmann::ordered_json;

namespace {

// A 30 x 30 m tile (0.09 ha): a sedan at (10, 10) heading 30, cover 0.1; a tank at (20, 20)
// heading 90, cover 0.8. UTM-sized offsets test that nothing loses precision.
const double E = 500000, N = 5400000;

std::string truth_text() {
  Json j{{"format", "canopy.scene_truth"},
         {"version", 1},
         {"extent", {30, 30}},
         {"vehicles",
          {{{"instance", 1},
            {"model", "sedan"},
            {"pose", {{"x", E + 10}, {"y", N + 10}, {"z", 100}, {"heading", 30}, {"pitch", 0}, {"roll", 0}}},
            {"canopy_cover", 0.1}},
           {{"instance", 2},
            {"model", "tank"},
            {"pose", {{"x", E + 20}, {"y", N + 20}, {"z", 100}, {"heading", 90}, {"pitch", 0}, {"roll", 0}}},
            {"canopy_cover", 0.8}}}}};
  return j.dump();
}

Json det(const std::string& id, const std::string& model, double conf, double x, double y, double heading) {
  return Json{
      {"candidate", id},
      {"model", model},
      {"confidence", conf},
      {"pose", {{"x", E + x}, {"y", N + y}, {"z", 100}, {"heading", heading}, {"pitch", 0}, {"roll", 0}}}};
}

// (A one-element brace list is the element itself in nlohmann's initializer lists.)
std::string detections_text(Json dets, int none = 0) {
  if (!dets.is_array()) dets = Json::array({dets});
  const int candidates = static_cast<int>(dets.size()) + none;
  return Json{{"format", "canopy.detections"},
              {"version", 1},
              {"candidates", candidates},
              {"none", none},
              {"detections", dets}}
      .dump();
}

// The score as its document's JSON (documents::write_scene_score).
Json as_json(const documents::SceneScore& s) { return Json::parse(documents::write_scene_score(s, {})); }

Json run(const Json& dets, score::Params p = {}) {
  score::Tile t;
  t.truth = score::parse_truth(truth_text(), "truth.json");
  t.detections = score::parse_detections(detections_text(dets), "detections.json");
  return as_json(score::score({t}, p));
}

const Json& all(const Json& s) { return s["summary"][0]; }

}  // namespace

TEST_CASE("heading error is modulo 360 and a flip is 180") {
  CHECK(score::heading_error(30, 32) == Approx(2));
  CHECK(score::heading_error(-178, 179) == Approx(3));
  CHECK(score::heading_error(30, 210) == Approx(180));
  CHECK(score::heading_error(10, 370) == Approx(0).margin(1e-12));
  CHECK(score::heading_error(0, 720 + 91) == Approx(91));
}

TEST_CASE("percentile interpolates between order statistics") {
  CHECK(score::percentile({3, 1, 2}, 50) == Approx(2));
  CHECK(score::percentile({1, 2}, 50) == Approx(1.5));
  CHECK(score::percentile({1, 2}, 90) == Approx(1.9));
  CHECK(score::percentile({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 90) == Approx(9.1));
  CHECK(std::isnan(score::percentile({}, 50)));
}

TEST_CASE("perfect detections: precision, recall, F1 and identification 1") {
  // Position errors 0.5 m each (0.3, 0.4) and (0, 0.5); heading errors 2 and 1 degrees.
  const Json s = run({det("c1", "sedan", 0.9, 10.3, 10.4, 32), det("c2", "tank", 0.8, 20, 20.5, 89)});
  const Json& a = all(s);
  CHECK(a["tp"] == 2);
  CHECK(a["fp"] == 0);
  CHECK(a["fn"] == 0);
  CHECK(a["precision"].get<double>() == Approx(1));
  CHECK(a["recall"].get<double>() == Approx(1));
  CHECK(a["f1"].get<double>() == Approx(1));
  CHECK(a["false_alarms_per_ha"].get<double>() == Approx(0));
  CHECK(a["area_ha"].get<double>() == Approx(0.09));
  CHECK(a["identification"].get<double>() == Approx(1));
  CHECK(a["recognition"].get<double>() == Approx(1));
  CHECK(a["position_error_median_m"].get<double>() == Approx(0.5).epsilon(1e-6));
  CHECK(a["heading_error_median_deg"].get<double>() == Approx(1.5));
  CHECK(a["heading_error_p90_deg"].get<double>() == Approx(1.9));
  CHECK(a["flips"] == 0);
}

TEST_CASE("one missed vehicle: recall 1/2, F1 2/3") {
  const Json s = run({det("c1", "sedan", 0.9, 10, 10, 30)});
  const Json& a = all(s);
  CHECK(a["tp"] == 1);
  CHECK(a["fp"] == 0);
  CHECK(a["fn"] == 1);
  CHECK(a["precision"].get<double>() == Approx(1));
  CHECK(a["recall"].get<double>() == Approx(0.5));
  CHECK(a["f1"].get<double>() == Approx(2.0 / 3));
  CHECK(a["recognition"].get<double>() == Approx(0.5));
  // The missed tank is a row of its own; per cover bin the tank (0.8) is missed, the sedan (0.1) found.
  int missed = 0;
  for (const auto& r : s["matches"]) {
    if (r["outcome"] == "missed") {
      ++missed;
      CHECK(r["instance"] == 2);
    }
  }
  CHECK(missed == 1);
  for (const auto& b : s["cover_bins"]) {
    if (b["cover_lo"] == 0.0) CHECK((b["true"] == 1 && b["detected"] == 1));
    if (b["cover_lo"] == 0.75) CHECK((b["true"] == 1 && b["detected"] == 0));
    if (b["cover_lo"] == 0.25 || b["cover_lo"] == 0.5) CHECK(b["true"] == 0);
  }
}

TEST_CASE("one false alarm: precision 2/3, 11.1 false alarms per hectare, PR curve") {
  const Json s = run({det("c1", "sedan", 0.9, 10, 10, 30), det("c2", "tank", 0.8, 20, 20, 90),
                      det("c3", "semi", 0.95, 5, 25, 0)});
  const Json& a = all(s);
  CHECK(a["tp"] == 2);
  CHECK(a["fp"] == 1);
  CHECK(a["precision"].get<double>() == Approx(2.0 / 3));
  CHECK(a["recall"].get<double>() == Approx(1));
  CHECK(a["f1"].get<double>() == Approx(0.8));
  CHECK(a["false_alarms_per_ha"].get<double>() == Approx(1 / 0.09));
  // Thresholds in falling confidence: 0.95 (only the false alarm), 0.9, 0.8.
  const Json& pr = s["pr"];
  REQUIRE(pr.size() == 3);
  CHECK(pr[0]["threshold"] == 0.95);
  CHECK(pr[0]["precision"].get<double>() == Approx(0));
  CHECK(pr[0]["recall"].get<double>() == Approx(0));
  CHECK(pr[1]["precision"].get<double>() == Approx(0.5));
  CHECK(pr[1]["recall"].get<double>() == Approx(0.5));
  CHECK(pr[2]["precision"].get<double>() == Approx(2.0 / 3));
  CHECK(pr[2]["recall"].get<double>() == Approx(1));
}

TEST_CASE("a duplicate detection: the more confident one matches, the other is a false alarm") {
  const Json s = run({det("c1", "sedan", 0.7, 10.2, 10, 30), det("c2", "sedan", 0.9, 10.1, 10, 30),
                      det("c3", "tank", 0.8, 20, 20, 90)});
  const Json& a = all(s);
  CHECK(a["tp"] == 2);
  CHECK(a["fp"] == 1);
  CHECK(a["precision"].get<double>() == Approx(2.0 / 3));
  CHECK(a["recall"].get<double>() == Approx(1));
  for (const auto& r : s["matches"]) {
    if (r["candidate"] == "c1") CHECK(r["outcome"] == "false_alarm");
    if (r["candidate"] == "c2") CHECK(r["outcome"] == "right");
  }
}

TEST_CASE("a flipped heading is matched and identified but its heading error is 180") {
  const Json s = run({det("c1", "sedan", 0.9, 10, 10, 210), det("c2", "tank", 0.8, 20, 20, 90)});
  const Json& a = all(s);
  CHECK(a["precision"].get<double>() == Approx(1));
  CHECK(a["recall"].get<double>() == Approx(1));
  CHECK(a["identification"].get<double>() == Approx(1));
  CHECK(a["flips"] == 1);
  CHECK(a["heading_error_median_deg"].get<double>() == Approx(90));  // errors 180 and 0
  CHECK(a["heading_error_p90_deg"].get<double>() == Approx(162));
}

TEST_CASE("a wrong model counts as detected, not identified") {
  const Json s = run({det("c1", "sedan", 0.9, 10, 10, 30), det("c2", "semi", 0.8, 20, 20, 90)});
  const Json& a = all(s);
  CHECK(a["precision"].get<double>() == Approx(1));
  CHECK(a["recall"].get<double>() == Approx(1));
  CHECK(a["identified"] == 1);
  CHECK(a["identification"].get<double>() == Approx(0.5));
  CHECK(a["recognition"].get<double>() == Approx(0.5));
  // Pose errors only over correctly identified detections: one (0 m, 0 degrees).
  CHECK(a["heading_error_median_deg"].get<double>() == Approx(0).margin(1e-12));
  bool tank_row = false;
  for (const auto& m : s["models"]) {
    if (m["model"] == "tank" && m["cover"] == "all") {
      tank_row = true;
      CHECK(m["matched"] == 1);
      CHECK(m["identified"] == 0);
    }
  }
  CHECK(tank_row);
  // Reliability: the semi at 0.8 is a wrong answer, the sedan at 0.9 a right one (one tile, one
  // render: Wilson on the counts, 0/1 -> [0, 0.7935]).
  CHECK(s["reliability"][8]["answers"] == 1);
  CHECK(s["reliability"][8]["right"] == 0);
  CHECK(s["reliability"][8]["rate_hi"].get<double>() == Approx(0.7935).margin(1e-4));
  CHECK(s["reliability"][9]["right"] == 1);
}

TEST_CASE("the match radius is 1.5 m on the horizontal centre distance") {
  // 1.6 m away: a false alarm and a miss; 1.4 m away: a match.
  Json s = run({det("c1", "sedan", 0.9, 11.6, 10, 30)});
  CHECK(all(s)["tp"] == 0);
  CHECK(all(s)["fp"] == 1);
  CHECK(all(s)["fn"] == 2);
  CHECK(all(s)["precision"].get<double>() == Approx(0));
  CHECK(all(s)["f1"].get<double>() == Approx(0));
  s = run({det("c1", "sedan", 0.9, 11.4, 10, 30)});
  CHECK(all(s)["tp"] == 1);
  score::Params wide;
  wide.match_radius = 2;
  s = run({det("c1", "sedan", 0.9, 11.6, 10, 30)}, wide);
  CHECK(all(s)["tp"] == 1);
}

TEST_CASE("no detections: precision undefined, recall 0") {
  const Json s = run(Json::array());
  CHECK(all(s)["precision"].is_null());
  CHECK(all(s)["recall"].get<double>() == Approx(0));
  CHECK(all(s)["f1"].is_null());
  CHECK(s["pr"].empty());
}

TEST_CASE("bad documents are refused naming the file and the field") {
  CHECK_THROWS_WITH(score::parse_truth("{", "t.json"), Catch::Contains("t.json"));
  CHECK_THROWS_WITH(score::parse_truth(R"({"format":"canopy.detections","version":1})", "t.json"),
                    Catch::Contains("expected \"canopy.scene_truth\""));
  CHECK_THROWS_WITH(score::parse_detections(R"({"format":"canopy.detections","version":3})", "d.json"),
                    Catch::Contains("version 3"));
  Json bad = Json::parse(detections_text({det("c1", "sedan", 1.5, 10, 10, 30)}));
  CHECK_THROWS_WITH(score::parse_detections(bad.dump(), "d.json"),
                    Catch::Contains("detections[0].confidence"));
  bad = Json::parse(detections_text({det("c1", "sedan", 0.5, 10, 10, 30), det("c1", "tank", 0.5, 20, 20, 0)}));
  CHECK_THROWS_WITH(score::parse_detections(bad.dump(), "d.json"), Catch::Contains("repeats"));
  Json t = Json::parse(truth_text());
  t["vehicles"][1]["pose"].erase("heading");
  CHECK_THROWS_WITH(score::parse_truth(t.dump(), "t.json"),
                    Catch::Contains("vehicles[1].pose: missing \"heading\""));
}

TEST_CASE("score CLI: two tiles by manifest, groups per cover and noise, CSV tables") {
  const auto dir = test::fresh_dir("score", "cli");
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream((dir / name).string()) << text;
  };
  write("truth.json", truth_text());
  // Tile A (light, 0 mm): perfect. Tile B (dense, 8 mm): the tank missed, one false alarm.
  write("a.json", detections_text({det("c1", "sedan", 0.9, 10, 10, 30), det("c2", "tank", 0.8, 20, 20, 90)}));
  write("b.json", detections_text({det("c1", "sedan", 0.6, 10, 10, 30), det("c2", "semi", 0.7, 2, 2, 0)}, 1));
  write("tiles.txt", "# detections truth noise cover\n" + (dir / "a.json").string() + " " +
                         (dir / "truth.json").string() + " 0 light\n" + (dir / "b.json").string() + " " +
                         (dir / "truth.json").string() + " 8 dense\n");
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/score";
  std::string err;
  const std::string cmd = bin + " -q --tiles " + (dir / "tiles.txt").string() + " -o " +
                          (dir / "score.json").string() + " --csv " + (dir / "s_").string();
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  std::ifstream f((dir / "score.json").string());
  const Json s = Json::parse(f);
  CHECK(s["format"] == "canopy.scene_score");
  const Json& a = s["summary"][0];
  CHECK(a["tiles"] == 2);
  CHECK(a["true"] == 4);
  CHECK(a["tp"] == 3);
  CHECK(a["fp"] == 1);
  CHECK(a["fn"] == 1);
  CHECK(a["precision"].get<double>() == Approx(0.75));
  CHECK(a["recall"].get<double>() == Approx(0.75));
  CHECK(a["candidates"] == 5);
  CHECK(a["none"] == 1);
  CHECK(a["false_alarms_per_ha"].get<double>() == Approx(1 / 0.18));
  // Groups: all, light, dense, 0 mm, 8 mm, light x 0, light x 8 (empty), dense x 0 (empty), dense x 8.
  REQUIRE(s["summary"].size() == 9);
  CHECK(s["summary"][1]["cover"] == "light");
  CHECK(s["summary"][1]["recall"].get<double>() == Approx(1));
  CHECK(s["summary"][2]["cover"] == "dense");
  CHECK(s["summary"][2]["recall"].get<double>() == Approx(0.5));
  CHECK(s["summary"][2]["precision"].get<double>() == Approx(0.5));
  CHECK(s["summary"][4]["noise_mm"] == 8.0);
  CHECK(s["summary"][4]["recall"].get<double>() == Approx(0.5));
  CHECK(s["summary"][6]["tiles"] == 0);
  CHECK(s["summary"][6]["recall"].is_null());
  // Cover bins overall: the two sedans (0.1) both found, of the two tanks (0.8) one.
  CHECK(s["cover_bins"][0]["recall"].get<double>() == Approx(1));
  CHECK(s["cover_bins"][3]["recall"].get<double>() == Approx(0.5));
  for (const char* t : {"summary", "pr", "models", "cover_bins", "reliability", "clutter", "matches"}) {
    INFO(t);
    CHECK(test::exists(dir / (std::string("s_") + t + ".csv")));
  }
  // A directory as the prefix (make's results/scenes/).
  std::filesystem::create_directories(dir / "tables");
  REQUIRE(test::sh(bin + " -q --tiles " + (dir / "tiles.txt").string() + " -o " + (dir / "s2.json").string() +
                       " --csv " + (dir / "tables").string() + "/",
                   dir / "err.txt", &err) == 0);
  CHECK(test::exists(dir / "tables" / "summary.csv"));
  std::ifstream c((dir / "s_summary.csv").string());
  std::string header, row;
  std::getline(c, header);
  std::getline(c, row);
  // (both tiles score one truth file: one render, its 2 vehicles counted once in true_distinct)
  CHECK(header.rfind("cover,noise_mm,tiles,renders,area_ha,true,true_distinct,", 0) == 0);
  CHECK(row.rfind("all,all,2,1,0.18,4,2,", 0) == 0);
  // Same inputs, same bytes.
  std::ifstream f1((dir / "score.json").string());
  std::stringstream b1, b2;
  b1 << f1.rdbuf();
  f1.close();
  REQUIRE(test::sh(cmd, dir / "err.txt", &err) == 0);
  std::ifstream f2((dir / "score.json").string());
  b2 << f2.rdbuf();
  CHECK(b1.str() == b2.str());
}

TEST_CASE("intervals: renders resampled, noise levels of one render counted once") {
  // Three renders (truth files r0, r1, r2; 2 vehicles each, 30 m x 30 m), each at two noise
  // levels: 6 tiles, 12 vehicle-runs, 6 distinct vehicles.
  auto tile = [](int render, double noise, const Json& dets) {
    score::Tile t;
    t.truth = score::parse_truth(truth_text(), "r" + std::to_string(render) + "/truth.json");
    t.detections = score::parse_detections(detections_text(dets), "d.json");
    t.noise_mm = noise;
    t.cover = "light";
    return t;
  };
  const Json both = Json::array({det("c1", "sedan", 0.9, 10, 10, 30), det("c2", "tank", 0.8, 20, 20, 90)});
  std::vector<score::Tile> tiles;
  for (int r = 0; r < 3; ++r) {
    for (double n : {0.0, 8.0}) tiles.push_back(tile(r, n, both));
  }
  const Json s = as_json(score::score(tiles, score::Params{}));
  const Json& a = s["summary"][0];
  CHECK(a["tiles"] == 6);
  CHECK(a["renders"] == 3);
  CHECK(a["true"] == 12);
  CHECK(a["true_distinct"] == 6);
  // Every render right: the bootstrap has no spread, so the interval is Wilson's at the 6
  // distinct vehicles, 6/6 -> [0.6097, 1] (not 12/12 -> [0.7575, 1] of the vehicle-runs).
  CHECK(a["recall"].get<double>() == Approx(1));
  CHECK(a["recall_lo"].get<double>() == Approx(0.6097).margin(1e-4));
  CHECK(a["recall_hi"].get<double>() == Approx(1));
  // One noise level alone: 6 runs of 3 renders, each run its own render: Wilson 6/6 again.
  const Json& zero = s["summary"][2];
  REQUIRE(zero["noise_mm"] == 0.0);
  CHECK(zero["renders"] == 3);
  CHECK(zero["true_distinct"] == 6);
  CHECK(zero["recall_lo"].get<double>() == Approx(0.6097).margin(1e-4));
  // No false alarm on 0.54 ha (at the effective 0.27 ha): exact Poisson 0 -> [0, 3.689] / 0.27.
  CHECK(a["false_alarms_per_ha_lo"].get<double>() == Approx(0));
  CHECK(a["false_alarms_per_ha_hi"].get<double>() == Approx(3.6889 / 0.27).epsilon(1e-3));
  // Nothing class-level: the rate and its bounds null.
  CHECK(a["class_accuracy"].is_null());
  CHECK(a["class_accuracy_lo"].is_null());
  CHECK(a["class_accuracy_hi"].is_null());
  // Models: the sedan 6 runs, 3 distinct, recall [Wilson 3/3 = 0.4385, 1].
  const Json& sedan = s["models"][0];
  REQUIRE(sedan["model"] == "sedan");
  CHECK(sedan["true"] == 6);
  CHECK(sedan["true_distinct"] == 3);
  CHECK(sedan["recall_lo"].get<double>() == Approx(0.4385).margin(1e-4));
  // Cover bins (all noise): the two sedans per render at cover 0.1 in [0, 0.25).
  CHECK(s["cover_bins"][0]["true_distinct"] == 3);
  CHECK(s["cover_bins"][0]["recall_lo"].get<double>() == Approx(0.4385).margin(1e-4));

  // Reliability: the model level's answers by confidence (the tank at 0.8, the sedan at 0.9),
  // all right: 6 answers per bin from 3 renders, Wilson at 3 -> [0.4385, 1]; the class level
  // has none (30 rows: 10 bins per level: model, class, none).
  REQUIRE(s["reliability"].size() == 30);
  const Json& r8 = s["reliability"][8];
  CHECK(r8["level"] == "model");
  CHECK(r8["confidence_lo"].get<double>() == Approx(0.8));
  CHECK(r8["answers"] == 6);
  CHECK(r8["right"] == 6);
  CHECK(r8["mean_confidence"].get<double>() == Approx(0.8));
  CHECK(r8["rate_lo"].get<double>() == Approx(0.4385).margin(1e-4));
  CHECK(s["reliability"][9]["answers"] == 6);  // 0.9 falls in [0.9, 1]
  CHECK(s["reliability"][7]["answers"] == 0);
  CHECK(s["reliability"][7]["rate"].is_null());
  CHECK(s["reliability"][18]["level"] == "class");
  CHECK(s["reliability"][18]["answers"] == 0);

  // Render r2 loses both vehicles at both noise levels: recall 8/12. The renders differ, so
  // the bootstrap over them reaches far below Wilson's interval at 6 vehicles (4/6 ->
  // [0.300, 0.903]): a draw of r2 three times gives 0 (probability 1/27 > 2.5%).
  tiles[4] = tile(2, 0, Json::array());
  tiles[5] = tile(2, 8, Json::array());
  const Json s2 = as_json(score::score(tiles, score::Params{}));
  const Json& b = s2["summary"][0];
  CHECK(b["recall"].get<double>() == Approx(8.0 / 12));
  CHECK(b["recall_lo"].get<double>() == Approx(0));
  CHECK(b["recall_hi"].get<double>() == Approx(1));
  CHECK(b["recall_lo"].get<double>() <= b["recall"].get<double>());
}

TEST_CASE("reliability of none: a rejection is wrong only where it cost a vehicle") {
  // The sedan found; the tank missed. Rejected: c2 beside the missed tank (0.70: wrong), c3 a
  // fragment of the found sedan (0.75: right), c4 on open ground (0.95: right), c5 without a
  // position (an older collect: not judged).
  Json d = Json::parse(detections_text(det("c1", "sedan", 0.9, 10, 10, 30), 4));
  d["rejected"] = Json::array({Json{{"candidate", "c2"},
                                    {"reason", "none"},
                                    {"confidence", 0.7},
                                    {"position", {{"x", E + 20.5}, {"y", N + 20}}}},
                               Json{{"candidate", "c3"},
                                    {"reason", "none"},
                                    {"confidence", 0.75},
                                    {"position", {{"x", E + 10.2}, {"y", N + 10}}}},
                               Json{{"candidate", "c4"},
                                    {"reason", "vegetation_like"},
                                    {"confidence", 0.95},
                                    {"position", {{"x", E + 2}, {"y", N + 2}}}},
                               Json{{"candidate", "c5"}, {"reason", "none"}, {"confidence", 0.5}}});
  score::Tile t;
  t.truth = score::parse_truth(truth_text(), "truth.json");
  t.detections = score::parse_detections(d.dump(), "detections.json");
  REQUIRE(t.detections.rejected.size() == 3);
  const Json s = as_json(score::score({t}, score::Params{}));
  const Json& rel = s["reliability"];
  REQUIRE(rel.size() == 30);
  CHECK(rel[27]["level"] == "none");
  CHECK(rel[27]["confidence_lo"].get<double>() == Approx(0.7));
  CHECK(rel[27]["answers"] == 2);
  CHECK(rel[27]["right"] == 1);
  CHECK(rel[29]["answers"] == 1);
  CHECK(rel[29]["right"] == 1);
  CHECK(rel[25]["answers"] == 0);  // c5 has no position
  // A malformed position or confidence is refused naming the member.
  d["rejected"][0]["position"] = Json{{"x", E}};
  CHECK_THROWS_WITH(score::parse_detections(d.dump(), "detections.json"),
                    Catch::Contains("rejected[0].position"));
  d["rejected"][0]["position"] = nullptr;
  d["rejected"][0]["confidence"] = 1.5;
  CHECK_THROWS_WITH(score::parse_detections(d.dump(), "detections.json"),
                    Catch::Contains("rejected[0].confidence"));
}

TEST_CASE("score CLI: a bad input names the file and writes nothing") {
  const auto dir = test::fresh_dir("score", "bad");
  std::ofstream((dir / "truth.json").string()) << truth_text();
  std::ofstream((dir / "d.json").string()) << "{\"format\": \"canopy.detections\"";
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/score";
  std::string err;
  CHECK(test::sh(bin + " -q -d " + (dir / "d.json").string() + " -t " + (dir / "truth.json").string() +
                     " -o " + (dir / "s.json").string(),
                 dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("d.json"));
  CHECK_FALSE(test::exists(dir / "s.json"));
  CHECK(test::sh(bin + " -q -d " + (dir / "d.json").string() + " -o " + (dir / "s.json").string(),
                 dir / "err.txt", &err) == 2);
}

TEST_CASE("the score document: the provenance after format and version, the score after it") {
  score::Inputs in;
  score::Tile t;
  t.truth = score::parse_truth(truth_text(), "truth.json");
  t.detections = score::parse_detections(detections_text(Json::array()), "detections.json");
  in.tiles = {t};
  in.provenance = {"score", "9.9", {{"csv", ""}}, {"detections.json", "truth.json"}};
  const Json doc =
      Json::parse(documents::write_scene_score(score::score(in.tiles, score::Params{}), in.provenance));
  std::vector<std::string> keys;
  for (const auto& [k, v] : doc.items()) keys.push_back(k);
  CHECK(keys == std::vector<std::string>{"format", "version", "provenance", "params", "tiles", "summary",
                                         "pr", "models", "cover_bins", "reliability", "clutter", "matches"});
  CHECK(doc["provenance"].dump() ==
        R"({"tool":"score","version":"9.9","parameters":{"csv":""},"inputs":["detections.json","truth.json"]})");
  CHECK(doc["summary"] == as_json(score::score(in.tiles, score::Params{}))["summary"]);
}

TEST_CASE("score parameters out of range name their option") {
  score::Params p;
  CHECK_NOTHROW(score::validate(p));
  p.match_radius = 0;
  CHECK_THROWS_WITH(score::validate(p), Catch::Contains("--match-radius"));
  p = {};
  p.flip_threshold = 181;
  CHECK_THROWS_WITH(score::validate(p), Catch::Contains("--flip-threshold"));
  p = {};
  p.cover_bins = {0.5};
  CHECK_THROWS_WITH(score::validate(p), Catch::Contains("--cover-bins"));
  p.cover_bins = {0, 0.5, 0.5, 1};
  CHECK_THROWS_WITH(score::validate(p), Catch::Contains("--cover-bins"));
  p.cover_bins = {0, 1.5};
  CHECK_THROWS_AS(score::validate(p), common::UsageError);
}

namespace {

// A class-level detection (canopy.detections v2): classify's class and group, heading modulo 180.
Json class_det(const std::string& id, const char* cls, const char* group, double conf, double x, double y,
               double heading) {
  Json d = det(id, "", conf, x, y, heading);
  d["level"] = "class";
  d["model"] = nullptr;
  d["class"] = cls;
  d["group"] = group;
  d["heading_ambiguity_deg"] = 180;
  return d;
}

Json run_v2(Json dets, const std::string& truth = truth_text()) {
  Json doc = Json::parse(detections_text(dets));
  doc["version"] = 2;
  for (auto& d : doc["detections"]) {
    if (!d.contains("level")) d["level"] = "model";
  }
  score::Tile t;
  t.truth = score::parse_truth(truth, "truth.json");
  t.detections = score::parse_detections(doc.dump(), "detections.json");
  return as_json(score::score({t}, score::Params{}));
}

}  // namespace

TEST_CASE("v2: class-level detections match by position, are scored apart, heading modulo 180") {
  // The sedan found at the model level; a class-level "tank" answer (group tracked) on the tank
  // back to front (heading 90 + 180 + 1), and a class-level false alarm far away.
  const Json s =
      run_v2({det("c1", "sedan", 0.9, 10, 10, 30), class_det("c2", "tank", "tracked", 0.6, 20.3, 20, 271),
              class_det("c3", "sedan", "car", 0.7, 2, 28, 0)});
  const Json& a = all(s);
  // Model-level figures are those of the model-level detections alone.
  CHECK(a["detections"] == 1);
  CHECK(a["tp"] == 1);
  CHECK(a["fn"] == 1);
  CHECK(a["recognition"].get<double>() == Approx(0.5));
  CHECK(a["class_detections"] == 2);
  CHECK(a["class_tp"] == 1);
  CHECK(a["class_fp"] == 1);
  CHECK(a["class_identified"] == 1);  // its class "tank" names the truth's model
  CHECK(a["class_accuracy"].get<double>() == Approx(1));
  CHECK(a["class_heading_error_median_deg"].get<double>() == Approx(1));  // 181 modulo 180
  CHECK(a["class_position_error_median_m"].get<double>() == Approx(0.3));
  CHECK(a["found_any_level"] == 2);
  CHECK(a["recall_any_level"].get<double>() == Approx(1));
  CHECK(a["precision_any_level"].get<double>() == Approx(2.0 / 3));
  CHECK(a["false_alarms_any_level_per_ha"].get<double>() == Approx(1 / 0.09));
  CHECK(s["tiles"][0]["class_tp"] == 1);
  CHECK(s["tiles"][0]["fn_any_level"] == 0);
  int class_rows = 0, missed = 0;
  for (const auto& r : s["matches"]) {
    missed += r["outcome"] == "missed" ? 1 : 0;
    if (r["level"] != "class") continue;
    ++class_rows;
    if (r["candidate"] == "c2") {
      CHECK(r["outcome"] == "right");
      CHECK(r["heading_error_deg"].get<double>() == Approx(1));
    } else {
      CHECK(r["outcome"] == "false_alarm");
    }
  }
  CHECK(class_rows == 2);
  CHECK(missed == 0);  // the tank is found at the class level
}

TEST_CASE(
    "v2: a class-level detection never takes a vehicle the model level found; group or class identify") {
  // Both levels on the sedan: the model level keeps it, the class-level one is a false alarm.
  const Json s =
      run_v2({class_det("c2", "sedan", "car", 0.99, 10, 10, 30), det("c1", "sedan", 0.5, 10, 10, 30)});
  CHECK(all(s)["tp"] == 1);
  CHECK(all(s)["class_tp"] == 0);
  CHECK(all(s)["class_fp"] == 1);
  // Hand-labelled truth names groups ("car", "van"): the group identifies, the class need not.
  Json t = Json::parse(truth_text());
  t["vehicles"][0]["model"] = "car";
  t["vehicles"][1]["model"] = "van";
  const Json g = run_v2(
      {class_det("c1", "hatchback", "car", 0.9, 10, 10, 30), class_det("c2", "suv", "car", 0.9, 20, 20, 90)},
      t.dump());
  CHECK(all(g)["class_tp"] == 2);
  CHECK(all(g)["class_identified"] == 1);  // the van answered car is matched, not identified
  CHECK(all(g)["class_accuracy"].get<double>() == Approx(0.5));
  // A truth "class" (procedural families) identifies too.
  Json f = Json::parse(truth_text());
  f["vehicles"][0]["model"] = "family-sedan-903";
  f["vehicles"][0]["class"] = "sedan";
  CHECK(all(run_v2({class_det("c1", "sedan", "car", 0.9, 10, 10, 210)}, f.dump()))["class_identified"] == 1);
  // A v2 class-level detection needs a class or a group; a v2 detection its level.
  Json bad = Json::parse(detections_text({class_det("c1", "sedan", "car", 0.9, 10, 10, 30)}));
  bad["version"] = 2;
  bad["detections"][0].erase("class");
  bad["detections"][0]["group"] = nullptr;
  CHECK_THROWS_WITH(score::parse_detections(bad.dump(), "d.json"),
                    Catch::Contains("without a class or group"));
  bad["detections"][0].erase("level");
  CHECK_THROWS_WITH(score::parse_detections(bad.dump(), "d.json"),
                    Catch::Contains("detections[0]: missing \"level\""));
  // v1 still reads: every detection model level.
  const Json v1 = run({det("c1", "sedan", 0.9, 10, 10, 30)});
  CHECK(all(v1)["tp"] == 1);
  CHECK(all(v1)["class_detections"] == 0);
}

TEST_CASE("model classes: a class answer on a rendered model is judged by the model's class, at any level") {
  // The sedan answered at the model level as "hatch" (a wrong model of the right class), the
  // second vehicle a "semi" answered at the class level "semi-tractor" (group truck).
  Json t = Json::parse(truth_text());
  t["vehicles"][1]["model"] = "semi";
  Json doc = Json::parse(detections_text(
      {det("c1", "hatch", 0.9, 10.3, 10.4, 212), class_det("c2", "semi-tractor", "truck", 0.6, 20, 20, 93)}));
  doc["version"] = 2;
  doc["detections"][0]["level"] = "model";
  auto tiles = [&] {
    score::Tile tile;
    tile.truth = score::parse_truth(t.dump(), "truth.json");
    tile.detections = score::parse_detections(doc.dump(), "detections.json");
    return std::vector<score::Tile>{tile};
  };
  // Without classes: only the model's name can be right, and neither is.
  const Json plain = as_json(score::score(tiles(), score::Params{}));
  CHECK(all(plain)["class_right_any_level"] == 0);
  CHECK(all(plain)["class_accuracy_any_level"].get<double>() == Approx(0));
  // Axis errors of both found vehicles: 212 vs 30 -> 2; 93 vs 90 -> 3; positions 0.5 and 0.
  CHECK(all(plain)["heading_axis_error_any_level_median_deg"].get<double>() == Approx(2.5));
  CHECK(all(plain)["position_error_any_level_median_m"].get<double>() == Approx(0.25));
  const auto classes = documents::parse_model_classes(
      "model,class\n# thesis models\nsemi,semi-tractor\nsedan,sedan\n"
      "hatch,sedan\n",
      "classes.csv");
  CHECK(classes.size() == 3);
  auto with = tiles();
  score::apply_model_classes(with, classes);
  CHECK(with[0].truth.vehicles[1].cls == "semi-tractor");
  CHECK(with[0].detections.detections[0].cls == "sedan");
  const Json s = as_json(score::score(with, score::Params{}));
  CHECK(all(s)["class_right_any_level"] == 2);
  CHECK(all(s)["class_accuracy_any_level"].get<double>() == Approx(1));
  CHECK(all(s)["class_accuracy_any_level_lo"].get<double>() < 1);
  CHECK(all(s)["class_accuracy"].get<double>() == Approx(1));  // the class level alone: 1/1
  CHECK(all(s)["identified"] == 0);                            // "hatch" is not the sedan
  // Bad files name the file and the line.
  CHECK_THROWS_WITH(documents::parse_model_classes("semi,semi-tractor\n", "c.csv"),
                    Catch::Contains("c.csv") && Catch::Contains("header"));
  CHECK_THROWS_WITH(documents::parse_model_classes("model,class\nsemi,truck\nsemi,bus\n", "c.csv"),
                    Catch::Contains("line 3") && Catch::Contains("given twice"));
  CHECK_THROWS_WITH(documents::parse_model_classes("model,class\nsemi,Semi Tractor\n", "c.csv"),
                    Catch::Contains("line 2") && Catch::Contains("[a-z0-9-]"));
  CHECK_THROWS_WITH(documents::parse_model_classes("model,class\nsemi\n", "c.csv"),
                    Catch::Contains("expected 'model,class'"));
}

namespace {

// score's INFO line for detections `dets` (v2) on the two-vehicle tile.
std::string line_of(Json dets) {
  Json doc = Json::parse(detections_text(std::move(dets)));
  doc["version"] = 2;
  for (auto& d : doc["detections"]) {
    if (!d.contains("level")) d["level"] = "model";
  }
  score::Tile t;
  t.truth = score::parse_truth(truth_text(), "truth.json");
  t.detections = score::parse_detections(doc.dump(), "detections.json");
  return score::summary_line(1, score::score({t}, score::Params{}).summary.at(0));
}

}  // namespace

TEST_CASE("the one-line summary counts both levels, every rate with its count and interval") {
  // Class level only (every real tile so far): before stop 70 the line read "0 detections:
  // precision n/a, recall 0.000" although both vehicles were found. One render: the intervals
  // are Wilson's (2/2: [0.342, 1]; 1/2: [0.095, 0.905]).
  CHECK(line_of({class_det("c1", "sedan", "car", 0.9, 10, 10, 30),
                 class_det("c2", "car", "car", 0.8, 20, 20, 90)}) ==
        "1 tile, 2 true vehicles, 2 detections (0 model level, 2 class level): recall 2/2 = 1.000 [0.342, "
        "1.000], "
        "precision 2/2 = 1.000 [0.342, 1.000], class right 1/2 = 0.500 [0.095, 0.905], model identified 0/0 "
        "(n/a)");
  // Both levels: the sedan at the model level (right), the tank at the class level (right), a
  // class-level false alarm.
  CHECK(
      line_of({det("c1", "sedan", 0.9, 10, 10, 30), class_det("c2", "tank", "tracked", 0.6, 20.3, 20, 271),
               class_det("c3", "sedan", "car", 0.7, 2, 28, 0)}) ==
      "1 tile, 2 true vehicles, 3 detections (1 model level, 2 class level): recall 2/2 = 1.000 [0.342, "
      "1.000], "
      "precision 2/3 = 0.667 [0.208, 0.939], class right 2/2 = 1.000 [0.342, 1.000], model identified 1/1 = "
      "1.000 [0.207, 1.000]");
  // Nothing found: the rates without a denominator are n/a.
  CHECK(line_of(Json::array()) ==
        "1 tile, 2 true vehicles, 0 detections (0 model level, 0 class level): recall 0/2 = 0.000 [0.000, "
        "0.658], "
        "precision 0/0 (n/a), class right 0/0 (n/a), model identified 0/0 (n/a)");
}

TEST_CASE("score logs the summary line and writes the same JSON") {
  const auto dir = canopy::test::fresh_dir("score", "summary_line");
  Json doc = Json::parse(detections_text({class_det("c1", "sedan", "car", 0.9, 10, 10, 30)}));
  doc["version"] = 2;
  canopy::test::write_file(dir / "d.json", doc.dump());
  canopy::test::write_file(dir / "t.json", truth_text());
  std::string err;
  REQUIRE(canopy::test::sh(std::string(CANOPY_BIN_DIR) + "/score -d " + (dir / "d.json").string() + " -t " +
                               (dir / "t.json").string() + " -o " + (dir / "s.json").string(),
                           dir / "err.txt", &err) == 0);
  CHECK(
      err.find("score: 1 tile, 2 true vehicles, 1 detection (0 model level, 1 class level): recall 1/2 = "
               "0.500 [0.095, 0.905], precision 1/1 = 1.000 [0.207, 1.000], class right 1/1 = 1.000 [0.207, "
               "1.000], model identified 0/0 (n/a)\n") != std::string::npos);
  const Json s = Json::parse(canopy::test::read_text(dir / "s.json"));
  CHECK(s["summary"][0]["class_tp"] == 1);
  CHECK(s["summary"][0]["recall_any_level"].get<double>() == Approx(0.5));
}

TEST_CASE("a missed vehicle's fate: the nearest candidate within reach says why it was missed") {
  // Five hand-placed vehicles (instance: where): 1 (5, 5) refused twice nearby, the nearer
  // refusal (vegetation_like, 0.4 m) decides over the farther (too_sparse, 1.2 m); 2 (15, 5) and
  // 3 (16.2, 5) share one detection at (15.5, 5), which takes 2 (the nearer), so 3 is "taken";
  // 4 (5, 20) a 12 m long outline with a detection 5 m from its centre but inside the outline:
  // "off_centre"; 5 (25, 25) a refusal 2.5 m away, beyond the radius and without an outline:
  // "no_candidate".
  const auto vehicle = [](int id, double x, double y) {
    return Json{{"instance", id},
                {"model", "car"},
                {"pose", {{"x", E + x}, {"y", N + y}, {"z", 100}, {"heading", 0}, {"pitch", 0}, {"roll", 0}}},
                {"canopy_cover", 0}};
  };
  Json v4 = vehicle(4, 5, 20);
  v4["footprint"] = Json::array({Json::array({E - 1, N + 18.75}), Json::array({E + 11, N + 18.75}),
                                 Json::array({E + 11, N + 21.25}), Json::array({E - 1, N + 21.25})});
  const Json truth{{"format", "canopy.scene_truth"},
                   {"version", 1},
                   {"extent", {30, 30}},
                   {"vehicles", Json::array({vehicle(1, 5, 5), vehicle(2, 15, 5), vehicle(3, 16.2, 5), v4,
                                             vehicle(5, 25, 25)})}};
  Json d = Json::parse(
      detections_text(Json::array({det("c2", "car", 0.9, 15.5, 5, 0), det("c3", "car", 0.8, 10, 20, 0)}), 3));
  const auto refusal = [](const std::string& id, const std::string& reason, double density, double x, double y) {
    return Json{{"candidate", id},
                {"reason", reason},
                {"confidence", nullptr},
                {"position", {{"x", E + x}, {"y", N + y}}},
                {"density", density}};
  };
  d["rejected"] =
      Json::array({refusal("c1", "vegetation_like", 12.5, 5.4, 5), refusal("c4", "too_sparse", 2.5, 6.2, 5),
                   refusal("c5", "too_small", 30, 25, 27.5)});
  score::Tile t;
  t.truth = score::parse_truth(truth.dump(), "truth.json");
  t.detections = score::parse_detections(d.dump(), "detections.json");
  REQUIRE(t.detections.rejected.size() == 3);
  for (const score::Rejection& r : t.detections.rejected)
    CHECK_FALSE(r.confidence);  // no confidence: not the reliability table's
  const Json s = as_json(score::score({t}, score::Params{}));
  for (const auto& row : s["reliability"])
    if (row["level"] == "none") CHECK(row["answers"] == 0);
  std::map<int, Json> missed;
  for (const auto& r : s["matches"]) {
    if (r["outcome"] == "missed") {
      missed[r["instance"].get<int>()] = r;
    } else {
      CHECK(r["fate"].is_null());
    }
  }
  REQUIRE(missed.size() == 4);
  CHECK(missed.count(2) == 0);  // found by c2
  CHECK(missed[1]["fate"] == "refused");
  CHECK(missed[1]["fate_candidate"] == "c1");
  CHECK(missed[1]["fate_reason"] == "vegetation_like");
  CHECK(missed[1]["fate_density"].get<double>() == Approx(12.5));
  CHECK(missed[3]["fate"] == "taken");
  CHECK(missed[3]["fate_candidate"] == "c2");
  CHECK(missed[3]["fate_reason"].is_null());
  CHECK(missed[3]["fate_density"].is_null());
  CHECK(missed[4]["fate"] == "off_centre");
  CHECK(missed[4]["fate_candidate"] == "c3");
  CHECK(missed[5]["fate"] == "no_candidate");
  CHECK(missed[5]["fate_candidate"].is_null());
  // With a 3 m radius the refusal beside vehicle 5 reaches it.
  score::Params wide;
  wide.match_radius = 3;
  for (const auto& r : as_json(score::score({t}, wide))["matches"]) {
    if (r["outcome"] == "missed" && r["instance"] == 5) CHECK(r["fate_reason"] == "too_small");
  }
  // The document reads back with the fates; a fate that is not one of the four is refused.
  const documents::SceneScore back = documents::read_scene_score(s.dump(), "score.json");
  int fates = 0;
  for (const auto& m : back.matches) fates += m.fate ? 1 : 0;
  CHECK(fates == 4);
  Json bad = s;
  for (auto& r : bad["matches"])
    if (r["outcome"] == "missed") r["fate"] = "lost";
  CHECK_THROWS_WITH(documents::read_scene_score(bad.dump(), "score.json"),
                    Catch::Contains("score.json") && Catch::Contains("fate must be"));
  // A negative object density is refused naming the member.
  d["rejected"][0]["density"] = -1;
  CHECK_THROWS_WITH(score::parse_detections(d.dump(), "detections.json"),
                    Catch::Contains("rejected[0].density"));
}

TEST_CASE("the detections of another tile are refused naming both files") {
  // The tile of truth_text(): vehicles at (10, 10) and (20, 20) of a 30 m tile. A detection 500 m
  // away is no detection of it (the box of its vehicles grown by 30 + 10 m reaches 60 m); one at
  // 55 m, or a rejected candidate inside, is.
  score::Tile t;
  t.truth = score::parse_truth(truth_text(), "truth.json");
  t.detections = score::parse_detections(detections_text(det("c1", "sedan", 0.9, 500, 10, 30)), "far.json");
  CHECK_THROWS_WITH(score::check_same_tile(t), Catch::Contains("far.json") && Catch::Contains("truth.json") &&
                                                   Catch::Contains("another tile"));
  t.detections = score::parse_detections(detections_text(det("c1", "sedan", 0.9, 55, 10, 30)), "near.json");
  CHECK_NOTHROW(score::check_same_tile(t));
  Json d = Json::parse(detections_text(det("c1", "sedan", 0.9, 500, 10, 30), 1));
  d["rejected"] = Json::array(
      {Json{{"candidate", "c2"}, {"reason", "too_sparse"}, {"position", {{"x", E + 12}, {"y", N + 9}}}}});
  t.detections = score::parse_detections(d.dump(), "mixed.json");
  CHECK_NOTHROW(score::check_same_tile(t));
  // Nothing to compare: no detection and no positioned rejection.
  t.detections = score::parse_detections(detections_text(Json::array(), 3), "empty.json");
  CHECK_NOTHROW(score::check_same_tile(t));
  // The CLI: exit 1, both files named, no output.
  const auto dir = test::fresh_dir("score", "other-tile");
  std::ofstream((dir / "truth.json").string()) << truth_text();
  std::ofstream((dir / "d.json").string()) << detections_text(det("c1", "sedan", 0.9, 500, 10, 30));
  std::string err;
  CHECK(test::sh(std::string(CANOPY_BIN_DIR) + "/score -q -d " + (dir / "d.json").string() + " -t " +
                     (dir / "truth.json").string() + " -o " + (dir / "s.json").string(),
                 dir / "err.txt", &err) == 1);
  CHECK_THAT(err, Catch::Contains("d.json") && Catch::Contains("truth.json"));
  CHECK_FALSE(test::exists(dir / "s.json"));
}
