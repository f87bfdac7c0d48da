// documents/match_result.h: the match result gmatch writes and verify, report and famscore read
// — round trip, NULL matches, the derived margin (files before it read too), format checks.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "canopy/common/error.h"
#include "canopy/documents/match_result.h"

using namespace canopy::documents;
using Catch::Contains;

TEST_CASE("match result: JSON round-trip, NULL matches as null") {
  MatchResult r;
  r.provenance = {"gmatch", "0.1.0", {}, {"s.json"}};
  r.object = "s.json";
  r.error_form = "bounded";
  r.entropy = 1.5;
  ModelScore ms;
  ms.model = "tank";
  ms.score = 0.75;
  ms.rank = 1;
  ms.pairs = {{0, 2, 0.1}, {1, -1, 0}};
  r.models.push_back(ms);
  const std::string rt = serialize_match_result(r);
  CHECK(rt.find("\"model_segment\": null") != std::string::npos);
  const MatchResult rb = parse_match_result(rt, "m.json");
  CHECK(rb.models.at(0).pairs.at(1).model_segment == -1);
  CHECK(serialize_match_result(rb) == rt);
  CHECK_THROWS_WITH(parse_match_result(R"({"format": "canopy.segment_graph", "version": 1})", "g.json"),
                    Contains("expected \"canopy.match_result\""));
}

TEST_CASE("match result: margin = rank-1 score minus rank-2 score, optional when reading") {
  MatchResult r;
  r.provenance = {"gmatch", "0.1.0", {}, {"s.json"}};
  r.object = "s.json";
  r.error_form = "bounded";
  ModelScore a, b;
  a.model = "sedan";
  a.score = 0.8;
  a.rank = 1;
  b.model = "tank";
  b.score = 0.5;
  b.rank = 2;
  r.models = {b, a};  // the margin follows the ranks, not the order
  CHECK(match_margin(r) == 0.8 - 0.5);
  r.models = {a, b};
  std::string text = serialize_match_result(r);
  CHECK_THAT(text, Contains("\"margin\": 0.30000000000000004"));
  CHECK(match_margin(parse_match_result(text, "m.json")) == 0.8 - 0.5);
  // A file written before "margin" existed still reads.
  const auto at = text.find(" \"margin\"");
  text.erase(at, text.find('\n', at) + 1 - at);
  CHECK(text.find("margin") == std::string::npos);
  CHECK(parse_match_result(text, "old.json").models.size() == 2);
  r.models = {a};
  CHECK(std::isnan(match_margin(r)));
  CHECK_THAT(serialize_match_result(r), Contains("\"margin\": null"));
  CHECK(parse_match_result(serialize_match_result(r), "one.json").models.size() == 1);
}

TEST_CASE("match result: a model or pair that is not an object is malformed, naming the place and the file") {
  const std::string head = R"({"format": "canopy.match_result", "version": 1,
 "provenance": {"tool": "gmatch", "version": "0.1.0", "parameters": {}, "inputs": []},
 "object": "s.json", "error_form": "bounded", "entropy": 0, "models": )";
  CHECK_THROWS_MATCHES(parse_match_result(head + "[1]}", "m.json"), canopy::common::DataError,
                       Catch::Message("m.json: malformed match result: models[0] must be an object"));
  const std::string model =
      R"([{"model": "tank", "score": 1, "rank": 1, "error_unary": 0, "error_orientation": 0,
 "error_distance": 0, "error_coverage": 0, "error_total": 0, "pairs": [2]}]})";
  CHECK_THROWS_MATCHES(
      parse_match_result(head + model, "p.json"), canopy::common::DataError,
      Catch::Message("p.json: malformed match result: models[0].pairs[0] must be an object"));
}

TEST_CASE("match result: an optional pose per model, written only when set, read back bit for bit") {
  MatchResult r;
  r.provenance = {"baseline", "0.1.0", {}, {"samples.pcd"}};
  r.object = "samples.pcd";
  r.error_form = "bounded";
  ModelScore a, b;
  a.model = "sedan";
  a.score = 0.7;
  a.rank = 1;
  b.model = "tank";
  b.score = 0;
  b.rank = 2;
  r.models = {a, b};
  // Without poses (gmatch's files): no "pose" key at all, and none read back.
  const std::string plain = serialize_match_result(r);
  CHECK(plain.find("pose") == std::string::npos);
  CHECK_FALSE(parse_match_result(plain, "m.json").models.at(0).pose.has_value());
  // A heading of 30 degrees and a translation: the 16 numbers as given, in their order.
  const double c = std::cos(0.5235987755982988), s = std::sin(0.5235987755982988);
  r.models[0].pose = std::array<double, 16>{c, -s, 0, 1.25, s, c, 0, -2.5, 0, 0, 1, 0.125, 0, 0, 0, 1};
  const std::string posed = serialize_match_result(r);
  CHECK_THAT(posed, Contains("\"pose\": ["));
  const MatchResult rb = parse_match_result(posed, "h.json");
  REQUIRE(rb.models.at(0).pose.has_value());
  CHECK(*rb.models.at(0).pose == *r.models[0].pose);
  CHECK_FALSE(rb.models.at(1).pose.has_value());  // the model without a pose has none
  CHECK(serialize_match_result(rb) == posed);
  // The entry is otherwise what it was: only the pose key was added.
  r.models[0].pose.reset();
  CHECK(serialize_match_result(r) == plain);
  // "pose": null reads as no pose.
  std::string nulled = posed;
  const auto at = nulled.find("\"pose\": [");
  nulled.replace(at, nulled.find(']', at) + 1 - at, "\"pose\": null");
  CHECK_FALSE(parse_match_result(nulled, "n.json").models.at(0).pose.has_value());
}

TEST_CASE("match result: a pose that is not rigid is refused, reading and writing") {
  MatchResult r;
  r.provenance = {"baseline", "0.1.0", {}, {}};
  r.error_form = "bounded";
  ModelScore a;
  a.model = "sedan";
  a.rank = 1;
  a.pose = std::array<double, 16>{2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // a scale
  r.models = {a};
  CHECK_THROWS_WITH(serialize_match_result(r), Contains("models[0].pose: the 3 x 3 part is not a rotation"));
  r.models[0].pose = std::array<double, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::string text = serialize_match_result(r);
  const auto at = text.find("\"pose\": [");
  REQUIRE(at != std::string::npos);
  const std::string mirror = "\"pose\": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]";
  text.replace(at, text.find(']', at) + 1 - at, mirror);
  CHECK_THROWS_MATCHES(
      parse_match_result(text, "h.json"), canopy::common::DataError,
      Catch::Message("h.json: malformed match result: models[0].pose: the 3 x 3 part is a reflection"));
  text.replace(text.find(mirror), mirror.size(), "\"pose\": [1, 0, 0]");
  CHECK_THROWS_WITH(parse_match_result(text, "h.json"), Contains("models[0].pose must be a 4 x 4 matrix"));
}
