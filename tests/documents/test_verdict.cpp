// documents/verdict.h: the one canopy.verdict reader (verify's, baseline's and classify's
// answers) and verify's writer. Hand-written verdicts read back field by field; malformed ones
// refused naming the file and the problem; the writer reproduces the old verify output.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "canopy/common/error.h"
#include "canopy/documents/stage_outcome.h"
#include "canopy/documents/verdict.h"
#include "old_outputs.h"
#include "support/cli.h"

using namespace canopy;

namespace {

// verify's answer: model "sedan" (hypothesis 0 of 2), turned by 90 degrees about z and moved
// by (1, 2, 3); the tile transform a shift by (500000, 5400000, 100); classes present.
const char* const kVerify = R"({"format": "canopy.verdict", "version": 1,
 "provenance": {"tool": "verify", "version": "0.1.0", "parameters": {"seed": "7"}, "inputs": ["m.json"]},
 "candidate": "cands/c0001/samples.pcd", "model": "sedan", "confidence": 0.8,
 "pose": {"matrix": [0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1]},
 "pose_tile": {"matrix": [0, -1, 0, 500001, 1, 0, 0, 5400002, 0, 0, 1, 103, 0, 0, 0, 1]},
 "fit_rms": 0.01, "explained": 0.9, "free_space_violation": 0.05,
 "transform": {"matrix": [1, 0, 0, 500000, 0, 1, 0, 5400000, 0, 0, 1, 100, 0, 0, 0, 1]},
 "chosen": 0,
 "hypotheses": [
  {"model": "sedan", "gmatch_rank": 1, "gmatch_score": 0.7, "start": "pairs", "flipped": false,
   "pose": {"matrix": [0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1]}, "pose_tile": null,
   "fit_rms": 0.01, "explained": 0.9, "free_space_violation": 0.05, "score": 0.855, "flip_score": 0.2,
   "class": "sedan"},
  {"model": "van", "gmatch_rank": 2, "gmatch_score": 0.4, "start": "axes-flipped", "flipped": true,
   "pose": {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}, "pose_tile": null,
   "fit_rms": 0.05, "explained": 0.5, "free_space_violation": 0.3, "score": 0.35, "flip_score": 0.1,
   "class": null}],
 "class": "sedan", "nearest_instance": "sedan", "class_score": 0.855, "class_margin": 0.505})";

// classify's answer: a hatchback at (1, 0.5) heading 0, too few points for a model.
const char* const kClassify = R"({"format": "canopy.verdict", "version": 1,
 "provenance": {"tool": "classify", "version": "0.1.0", "parameters": {}, "inputs": []},
 "candidate": "cands/c0002.pcd", "level": "class", "model": null, "class": "hatchback", "group": "car",
 "confidence": 0.6, "reason": null, "detail": "",
 "pose": {"matrix": [1, 0, 0, 1, 0, 1, 0, 0.5, 0, 0, 1, 0, 0, 0, 0, 1]}, "pose_tile": null,
 "heading_ambiguity_deg": 180, "size": [4.1, 1.75, 1.5], "density": 42.5,
 "density_needed": {"class": 4, "model": 370}, "points": 300,
 "fit_rms": null, "explained": null, "free_space_violation": null, "transform": null,
 "chosen": -1, "hypotheses": [], "nearest_instance": null, "class_score": 0.7, "class_margin": 0.3})";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("verdict: verify's answer read field by field") {
  const documents::Verdict v = documents::parse_verdict(kVerify, "v.json");
  CHECK(v.provenance.tool == "verify");
  CHECK(v.provenance.parameters.size() == 1);
  CHECK(v.provenance.inputs == std::vector<std::string>{"m.json"});
  CHECK(v.candidate == "cands/c0001/samples.pcd");
  CHECK(v.model == "sedan");
  CHECK(v.confidence == 0.8);
  CHECK(v.chosen == 0);
  REQUIRE(v.hypotheses.size() == 2);
  CHECK(v.hypotheses[1].model == "van");
  CHECK(v.hypotheses[1].gmatch_rank == 2);
  CHECK(v.hypotheses[1].start == "axes-flipped");
  CHECK(v.hypotheses[1].flipped);
  CHECK(v.hypotheses[1].vehicle_class.empty());
  CHECK(v.hypotheses[0].score == 0.855);
  CHECK(v.hypotheses[0].vehicle_class == "sedan");
  const formats::Pose& p = v.hypotheses[0].pose;
  CHECK(p.rotation == std::array<double, 9>{0, -1, 0, 1, 0, 0, 0, 0, 1});
  CHECK(p.translation == std::array<double, 3>{1, 2, 3});
  CHECK(formats::euler_degrees(p)[0] == Approx(90));
  REQUIRE(v.pose_tile);
  CHECK(v.pose_tile->translation == std::array<double, 3>{500001, 5400002, 103});
  REQUIRE(v.transform);
  CHECK(v.transform->translation[2] == 100);
  CHECK(v.has_classes);
  CHECK(v.vehicle_class == "sedan");
  CHECK(v.nearest_instance == "sedan");
  CHECK(v.class_margin == 0.505);
  CHECK(v.level.empty());
  CHECK_FALSE(v.size);
}

TEST_CASE("verdict: classify's class-level answer read field by field") {
  const documents::Verdict v = documents::parse_verdict(kClassify, "class.json");
  CHECK(v.level == "class");
  CHECK(v.model.empty());
  CHECK(v.chosen == -1);
  CHECK(v.hypotheses.empty());
  CHECK(v.vehicle_class == "hatchback");
  CHECK(v.group == "car");
  CHECK(v.reason.empty());
  CHECK(v.detail.empty());
  REQUIRE(v.pose);
  CHECK(v.pose->translation == std::array<double, 3>{1, 0.5, 0});
  CHECK_FALSE(v.pose_tile);
  CHECK(v.heading_ambiguity == 180);
  REQUIRE(v.size);
  CHECK((*v.size)[1] == 1.75);
  CHECK(v.density == 42.5);
  CHECK(v.density_class == 4);
  CHECK(v.density_model == 370);
  CHECK(v.nearest_instance.empty());
  CHECK(v.class_score == 0.7);
}

TEST_CASE("verdict: malformed verdicts are refused naming the file and the problem") {
  struct Case {
    const char* from;
    const char* to;
    const char* why;
  };
  const Case cases[] = {
      // Not a rotation, a reflection, a projective last row, a 4 x 4 of rows (canopy writes 16).
      {"\"pose\": {\"matrix\": [0, -1, 0, 1, 1, 0", "\"pose\": {\"matrix\": [0, -1, 0.5, 1, 1, 0",
       "pose.matrix: the 3 x 3 part is not a rotation"},
      {"\"pose\": {\"matrix\": [0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3",
       "\"pose\": {\"matrix\": [0, -1, 0, 1, 1, 0, 0, 2, 0, 0, -1, 3",
       "pose.matrix: the 3 x 3 part is a reflection"},
      {"0, 0, 1, 103, 0, 0, 0, 1]", "0, 0, 1, 103, 0, 0, 0.5, 1]",
       "pose_tile.matrix: last row is not 0 0 0 1"},
      {"\"transform\": {\"matrix\": [1, 0, 0, 500000, 0, 1, 0, 5400000, 0, 0, 1, 100, 0, 0, 0, 1]}",
       "\"transform\": {\"matrix\": [[1, 0, 0, 500000], [0, 1, 0, 5400000], [0, 0, 1, 100], [0, 0, 0, 1]]}",
       "transform.matrix must be 16 numbers"},
      {"\"candidate\": \"cands/c0001/samples.pcd\"", "\"candidate\": \"\"", "candidate must name"},
      {"\"confidence\": 0.8", "\"confidence\": 1.5", "confidence outside [0, 1]"},
      {"\"model\": \"sedan\", \"confidence\"", "\"model\": \"../sedan\", \"confidence\"",
       "model must be a model name"},
      {"\"chosen\": 0", "\"chosen\": 2", "chosen is not -1 or a hypothesis index"},
      {"\"chosen\": 0", "\"chosen\": 1", "model and chosen disagree"},
      {"\"gmatch_rank\": 2", "\"gmatch_rank\": 2.5", "hypotheses[1].gmatch_rank must be an integer"},
      {"\"class\": \"sedan\", \"nearest", "\"class\": \"a/b\", \"nearest", "class must be a model name"},
      {"\"version\": 1", "\"version\": 2", "version"},
  };
  for (const Case& c : cases) {
    INFO(c.why);
    CHECK_THROWS_AS(documents::parse_verdict(replaced(kVerify, c.from, c.to), "dir/v.json"), common::DataError);
    CHECK_THROWS_WITH(documents::parse_verdict(replaced(kVerify, c.from, c.to), "dir/v.json"),
                      Catch::Contains("dir/v.json") && Catch::Contains(c.why));
  }
  // A model (or a class at class level) must stand somewhere: no pose, no pose_tile.
  std::string no_pose =
      replaced(kVerify,
               "\"pose\": {\"matrix\": [0, -1, 0, 1, 1, 0, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1]},\n \"pose_tile\": "
               "{\"matrix\": [0, -1, 0, 500001, 1, 0, 0, 5400002, 0, 0, 1, 103, 0, 0, 0, 1]}",
               "\"pose\": null, \"pose_tile\": null");
  CHECK_THROWS_WITH(documents::parse_verdict(no_pose, "v.json"),
                    Catch::Contains("v.json") && Catch::Contains("a model without a pose"));
  CHECK_THROWS_WITH(
      documents::parse_verdict(
          replaced(kClassify, "\"pose\": {\"matrix\": [1, 0, 0, 1, 0, 1, 0, 0.5, 0, 0, 1, 0, 0, 0, 0, 1]}",
                   "\"pose\": null"),
          "class.json"),
      Catch::Contains("class.json") && Catch::Contains("a class without a pose"));
  CHECK_THROWS_WITH(
      documents::parse_verdict(replaced(kClassify, "[4.1, 1.75, 1.5]", "[4.1, -1.75, 1.5]"), "class.json"),
      Catch::Contains("class.json") && Catch::Contains("size must be three numbers >= 0"));
  CHECK_THROWS_WITH(
      documents::parse_verdict(replaced(kClassify, "\"group\": \"car\"", "\"group\": 3"), "class.json"),
      Catch::Contains("class.json") && Catch::Contains("group must be a model name"));
  CHECK_THROWS_WITH(
      documents::parse_verdict("{\"format\": \"canopy.match_result\", \"version\": 1}", "w.json"),
      Catch::Contains("w.json"));
}

TEST_CASE("verdict: the writer reproduces verify's output of d83b7b7 byte for byte") {
  const documents::Verdict v = documents::parse_verdict(old_output::kVerifyNone, "verdict.json");
  CHECK(v.model.empty());
  CHECK(v.hypotheses.size() == 2);
  CHECK(documents::serialize_verdict(v) == old_output::kVerifyNone);
}

TEST_CASE("stage outcome: no file, an empty file (failed), a written verdict") {
  const auto dir = test::fresh_dir("documents", "stage_outcome");
  const std::string missing = (dir / "none.json").string(), empty = (dir / "empty.json").string(),
                    written = (dir / "v.json").string(), bad = (dir / "bad.json").string();
  test::write_file(empty, "");
  test::write_file(written, kVerify);
  test::write_file(bad, replaced(kVerify, "\"confidence\": 0.8", "\"confidence\": -1"));
  CHECK(documents::read_stage_output(missing).outcome == documents::StageOutcome::missing);
  CHECK(documents::read_stage_output(empty).outcome == documents::StageOutcome::failed);
  const documents::StageOutput w = documents::read_stage_output(written);
  CHECK(w.outcome == documents::StageOutcome::written);
  CHECK(w.text == kVerify);
  CHECK(documents::read_stage_verdict(missing).outcome == documents::StageOutcome::missing);
  CHECK(documents::read_stage_verdict(empty).outcome == documents::StageOutcome::failed);
  const documents::StageVerdict sv = documents::read_stage_verdict(written);
  CHECK(sv.outcome == documents::StageOutcome::written);
  CHECK(sv.verdict.model == "sedan");
  CHECK_THROWS_WITH(documents::read_stage_verdict(bad),
                    Catch::Contains(bad) && Catch::Contains("confidence"));
}

TEST_CASE("verdict: verify's null-hypothesis box is optional, read and written back") {
  const documents::Verdict plain = documents::parse_verdict(kVerify, "v.json");
  CHECK(!plain.box);  // older verdicts have none
  CHECK(documents::serialize_verdict(plain).find("\"box\"") == std::string::npos);
  const std::string with = replaced(kVerify, "\"class_margin\": 0.505}",
                                    "\"class_margin\": 0.505, \"box\": {\"explained\": 0.75, "
                                    "\"free_space_violation\": 0.5, \"score\": 0.375}}");
  const documents::Verdict v = documents::parse_verdict(with, "v.json");
  REQUIRE(v.box);
  CHECK(v.box->explained == 0.75);
  CHECK(v.box->free_space_violation == 0.5);
  CHECK(v.box->score == 0.375);
  const documents::Verdict again = documents::parse_verdict(documents::serialize_verdict(v), "again.json");
  REQUIRE(again.box);
  CHECK(again.box->score == 0.375);
  CHECK(again.box->explained == 0.75);
  CHECK_THROWS_WITH(
      documents::parse_verdict(replaced(with, "\"score\": 0.375}", "\"score\": \"x\"}"), "d/v.json"),
      Catch::Contains("d/v.json") && Catch::Contains("box.score must be a number"));
  CHECK_THROWS_WITH(
      documents::parse_verdict(
          replaced(kVerify, "\"class_margin\": 0.505}", "\"class_margin\": 0.505, \"box\": 1}"), "d/v.json"),
      Catch::Contains("d/v.json") && Catch::Contains("box must be an object"));
}
