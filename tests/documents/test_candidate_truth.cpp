// documents/candidate_truth.h: candtruth's candidate_truth.json writes and reads back; malformed
// files are refused naming the file and the member.
#include <catch2/catch.hpp>

#include <string>

#include <nlohmann/json.hpp>

#include "canopy/common/error.h"
#include "canopy/documents/candidate_truth.h"

using namespace canopy;

namespace {

documents::CandidateTruth sample() {
  documents::CandidateTruth t;
  t.tile = "tile.pcd";
  t.index = "cands/index.json";
  t.candidates = {{"c0001", 175, 1, 100, 0.8125, 0.8}, {"c0002", 30, 0, 0, 0, 0}};
  t.instances = {{1, 120, {"c0001"}}, {3, 5, {}}};
  return t;
}

std::string refusal(const nlohmann::ordered_json& j) {
  try {
    documents::read_candidate_truth(j.dump(), "t.json");
  } catch (const common::DataError& e) {
    CHECK(e.file() == "t.json");
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("candidate truth: written and read back, member for member") {
  const std::string text = documents::write_candidate_truth(sample(), {"candtruth", "0.1.0", {}, {"a", "b"}});
  const auto j = nlohmann::ordered_json::parse(text);
  CHECK(j["format"] == "canopy.candidate_truth");
  CHECK(j["version"] == 1);
  CHECK(j["provenance"]["tool"] == "candtruth");
  const documents::CandidateTruth t = documents::read_candidate_truth(text, "t.json");
  CHECK(t.tile == "tile.pcd");
  CHECK(t.index == "cands/index.json");
  REQUIRE(t.candidates.size() == 2);
  CHECK(t.candidates[0].id == "c0001");
  CHECK(t.candidates[0].crop_points == 175);
  CHECK(t.candidates[0].instance == 1);
  CHECK(t.candidates[0].points == 100);
  CHECK(t.candidates[0].coverage == 0.8125);
  CHECK(t.candidates[0].purity == 0.8);
  CHECK(t.candidates[1].instance == 0);
  REQUIRE(t.instances.size() == 2);
  CHECK(t.instances[0].candidates == std::vector<std::string>{"c0001"});
  CHECK(t.instances[1].points == 5);
  CHECK(t.instances[1].candidates.empty());
  CHECK(documents::write_candidate_truth(t, {"candtruth", "0.1.0", {}, {"a", "b"}}) == text);
}

TEST_CASE("candidate truth: refusals name the file and the member") {
  const auto good =
      nlohmann::ordered_json::parse(documents::write_candidate_truth(sample(), {"candtruth", "0", {}, {}}));
  CHECK(refusal(good).empty());
  auto share = good, id = good, twice = good, count = good, missing = good;
  share["candidates"][0]["coverage"] = 1.5;
  id["instances"][0]["candidates"][0] = "c0009";
  twice["candidates"][1]["id"] = "c0001";
  count["candidates"][0]["points"] = -1;
  missing["candidates"][1].erase("purity");
  CHECK_THAT(refusal(share), Catch::Contains("candidates[0].coverage must be a share in [0, 1]"));
  CHECK_THAT(refusal(id), Catch::Contains("\"c0009\" is not a candidate"));
  CHECK_THAT(refusal(twice), Catch::Contains("\"c0001\" repeats"));
  CHECK_THAT(refusal(count), Catch::Contains("candidates[0].points"));
  CHECK_THAT(refusal(missing), Catch::Contains("missing \"purity\""));
}
