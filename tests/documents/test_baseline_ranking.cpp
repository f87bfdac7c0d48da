// documents/baseline_ranking.h: the ranking `baseline` writes (every method's models best first)
// and report and famscore read; the writer's exact bytes, the reader's refusals naming the file.
#include <catch2/catch.hpp>
#include <string>

#include "canopy/common/error.h"
#include "canopy/documents/baseline_ranking.h"

using namespace canopy::documents;
using canopy::common::DataError;

TEST_CASE("canopy.baseline rankings: every method's models in order, errors naming the file") {
  const std::string doc =
      R"({"format": "canopy.baseline", "version": 1, "object": "s.pcd", "candidate_points": 9,
          "methods": [{"method": "vfh", "models": [{"rank": 1, "model": "sedan", "score": 0.74},
                                                   {"rank": 2, "model": "tank", "score": 0.5}]},
                      {"method": "fpfh", "models": [{"rank": 1, "model": "tank", "score": 0}]}]})";
  const auto r = parse_baseline_ranking(doc, "b.json");
  REQUIRE(r.size() == 2);
  CHECK(r[0].method == "vfh");
  REQUIRE(r[0].models.size() == 2);
  CHECK(r[0].models[0].model == "sedan");
  CHECK(r[0].models[0].score == 0.74);
  CHECK(!parse_baseline_ranking(R"({"format": "canopy.baseline", "methods": [{"method": "vfh",
      "models": [{"model": "sedan"}]}]})",
                                "b.json")[0]
             .models[0]
             .score);
  CHECK(r[0].models[1].model == "tank");
  CHECK(r[1].method == "fpfh");
  CHECK(r[1].models.at(0).score == 0.0);
  CHECK_THROWS_WITH(parse_baseline_ranking("{", "b.json"), Catch::Contains("not JSON"));
  CHECK_THROWS_WITH(parse_baseline_ranking(R"({"format": 3})", "b.json"),
                    Catch::Contains("not a canopy.baseline document"));
  CHECK_THROWS_WITH(
      parse_baseline_ranking(R"({"format": "canopy.baseline", "version": 2, "methods": []})", "b.json"),
      Catch::Contains("canopy.baseline version 2 is not supported"));
  CHECK_THROWS_WITH(parse_baseline_ranking(R"({"format": "canopy.verdict"})", "b.json"),
                    Catch::Contains("not a canopy.baseline document"));
  CHECK_THROWS_WITH(
      parse_baseline_ranking(R"({"format": "canopy.baseline", "methods": [{"method": "vfh"}]})", "b.json"),
      Catch::Contains("malformed canopy.baseline"));
  try {
    parse_baseline_ranking("[]", "dir/b.json");
    FAIL("no error");
  } catch (const DataError& e) { CHECK(e.file() == "dir/b.json"); }
}

TEST_CASE("canopy.baseline writer: vfh and fpfh keys, a pose or null, read back in order") {
  BaselineRanking r{{"baseline", "0.1.0", {{"seed", "1"}}, {"s.pcd", "mb"}}, "s.pcd", 9, {}};
  BaselineModel v;
  v.model = "sedan";
  v.rank = 1;
  v.score = 0.75;
  v.distance = 0.5;
  v.view = 3;
  r.methods.push_back({"vfh", {v}});
  BaselineModel a = v, b = v;
  a.fitness = 0.5;
  a.candidate_share = 0.25;
  a.model_share = 1;
  a.pose = std::array<double, 16>{1, 0, 0, 2, 0, 1, 0, 3, 0, 0, 1, 0, 0, 0, 0, 1};
  b.model = "tank";
  b.rank = 2;
  b.score = 0;
  r.methods.push_back({"fpfh", {a, b}});
  const std::string text = serialize_baseline_ranking(r);
  CHECK(text ==
        "{\n \"format\": \"canopy.baseline\",\n \"version\": 1,\n \"provenance\": {\n  \"tool\": "
        "\"baseline\",\n"
        "  \"version\": \"0.1.0\",\n  \"parameters\": {\n   \"seed\": \"1\"\n  },\n  \"inputs\": [\n   "
        "\"s.pcd\",\n"
        "   \"mb\"\n  ]\n },\n \"object\": \"s.pcd\",\n \"candidate_points\": 9,\n \"methods\": [\n  {\n"
        "   \"method\": \"vfh\",\n   \"models\": [\n    {\n     \"rank\": 1,\n     \"model\": \"sedan\",\n"
        "     \"score\": 0.75,\n     \"distance\": 0.5,\n     \"view\": 3\n    }\n   ]\n  },\n  {\n"
        "   \"method\": \"fpfh\",\n   \"models\": [\n    {\n     \"rank\": 1,\n     \"model\": \"sedan\",\n"
        "     \"score\": 0.75,\n     \"fitness\": 0.5,\n     \"candidate_share\": 0.25,\n"
        "     \"model_share\": 1.0,\n     \"pose\": [\n      1.0,\n      0.0,\n      0.0,\n      2.0,\n"
        "      0.0,\n      1.0,\n      0.0,\n      3.0,\n      0.0,\n      0.0,\n      1.0,\n      0.0,\n"
        "      0.0,\n      0.0,\n      0.0,\n      1.0\n     ]\n    },\n    {\n     \"rank\": 2,\n"
        "     \"model\": \"tank\",\n     \"score\": 0.0,\n     \"fitness\": 0.0,\n"
        "     \"candidate_share\": 0.0,\n     \"model_share\": 0.0,\n     \"pose\": null\n    }\n   ]\n"
        "  }\n ]\n}\n");
  const auto back = parse_baseline_ranking(text, "b.json");
  REQUIRE(back.size() == 2);
  REQUIRE(back[1].models.size() == 2);
  CHECK(back[1].models[0].model == "sedan");
  CHECK(back[1].models[1].model == "tank");
  CHECK(back[1].models[1].score == 0.0);
  b.score.reset();
  r.methods[1].models[1] = b;
  CHECK_THROWS_WITH(serialize_baseline_ranking(r), Catch::Contains("tank without a score"));
}
