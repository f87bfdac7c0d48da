// documents/classification.h: classify's class-level verdict. The writer, given what classify
// measured, reproduces classify's output of d83b7b7 byte for byte; the one verdict reader reads
// it back.
#include <catch2/catch.hpp>

#include <string>

#include <nlohmann/json.hpp>

#include "canopy/documents/classification.h"
#include "canopy/documents/verdict.h"
#include "old_outputs.h"

using namespace canopy;
using Json = nlohmann::ordered_json;

namespace {

std::optional<formats::Pose> pose_of(const Json& j) {
  if (j.is_null()) return std::nullopt;
  formats::Pose p;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) p.rotation[3 * r + c] = j["matrix"][4 * r + c].get<double>();
    p.translation[r] = j["matrix"][4 * r + 3].get<double>();
  }
  return p;
}

std::array<double, 3> triple(const Json& j) {
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}
std::string text(const Json& j) { return j.is_null() ? "" : j.get<std::string>(); }

// What classify measured, taken from its old output (the values, not the text).
documents::ClassVerdict measured(const std::string& old) {
  const Json j = Json::parse(old);
  documents::ClassVerdict v;
  const Json& prov = j["provenance"];
  v.provenance.tool = prov["tool"].get<std::string>();
  v.provenance.version = prov["version"].get<std::string>();
  for (const auto& [k, val] : prov["parameters"].items())
    v.provenance.parameters.emplace_back(k, val.get<std::string>());
  for (const auto& in : prov["inputs"]) v.provenance.inputs.push_back(in.get<std::string>());
  v.candidate = j["candidate"].get<std::string>();
  v.cls = text(j["class"]);
  v.group = text(j["group"]);
  v.reason = text(j["reason"]);
  v.detail = j["detail"].get<std::string>();
  v.confidence = j["confidence"];
  v.pose = pose_of(j["pose"]);
  v.pose_tile = pose_of(j["pose_tile"]);
  if (!j["size"].is_null()) v.size = triple(j["size"]);
  if (!j["measured"].is_null()) {
    const Json& m = j["measured"];
    v.measured = documents::MeasuredRectangle{triple(m["size"]),
                                              {m["centre"][0].get<double>(), m["centre"][1].get<double>()},
                                              m["heading_deg"],
                                              m["spacing"],
                                              m["edge_correction"]};
  }
  if (!j["density"].is_null()) v.density = j["density"].get<double>();
  v.density_needed_class = j["density_needed"]["class"];
  v.density_needed_model = j["density_needed"]["model"];
  v.points = j["points"];
  for (const auto& [k, val] : j["features"].items()) {
    documents::ClassFeature f{k, std::nullopt, val.is_number_integer()};
    if (!val.is_null()) f.value = val.get<double>();
    v.features.push_back(f);
  }
  if (!j["nearest"].is_null())
    v.nearest =
        documents::NearestModel{j["nearest"]["model"], j["nearest"]["class"], triple(j["nearest"]["size"])};
  v.transform = pose_of(j["transform"]);
  v.class_score = j["class_score"];
  v.class_margin = j["class_margin"];
  return v;
}

}  // namespace

TEST_CASE("classification: the writer reproduces classify's output of d83b7b7 byte for byte") {
  for (const char* old : {old_output::kClassifyTank, old_output::kClassifyTankNearest}) {
    const documents::ClassVerdict v = measured(old);
    CHECK(documents::serialize_class_verdict(v) == old);
  }
}

TEST_CASE("classification: a hand-built answer is read back by the verdict reader") {
  documents::ClassVerdict c;
  c.provenance = {"classify", "9.9", {{"min-density", "4"}}, {"c7.pcd"}};
  c.candidate = "cands/c7.pcd";
  c.cls = "van";
  c.group = "van";
  c.confidence = 0.5;
  formats::Pose p;
  p.rotation = {0, -1, 0, 1, 0, 0, 0, 0, 1};  // heading 90
  p.translation = {0.25, -0.5, 0};
  c.pose = p;
  formats::Pose shift;
  shift.translation = {500000, 5400000, 100};
  c.transform = shift;
  c.pose_tile = formats::Pose{p.rotation, {500000.25, 5399999.5, 100}};
  c.size = std::array<double, 3>{5.5, 2, 2.4};
  c.measured = documents::MeasuredRectangle{{5.4, 1.9, 2.35}, {0.25, -0.5}, 89.5, 0.3, 0.03};
  c.density = 12;
  c.density_needed_class = 4;
  c.density_needed_model = 370;
  c.points = 130;
  c.features = {{"crop_points", 400.0, true}, {"fill", std::nullopt, false}};
  c.nearest = documents::NearestModel{"van-1", "van", {5.4, 2.0, 2.3}};
  c.class_score = 0.9;
  c.class_margin = 0.4;
  const std::string text = documents::serialize_class_verdict(c);
  const Json j = Json::parse(text);
  CHECK(j["features"]["crop_points"].is_number_integer());
  CHECK(j["features"]["fill"].is_null());
  CHECK(j["heading_ambiguity_deg"] == 180);
  const documents::Verdict v = documents::parse_verdict(text, "class.json");
  CHECK(v.level == "class");
  CHECK(v.model.empty());
  CHECK(v.vehicle_class == "van");
  CHECK(v.group == "van");
  CHECK(v.confidence == 0.5);
  REQUIRE(v.pose);
  CHECK(formats::euler_degrees(*v.pose)[0] == Approx(90));
  REQUIRE(v.pose_tile);
  CHECK(v.pose_tile->translation == std::array<double, 3>{500000.25, 5399999.5, 100});
  CHECK(v.size == std::array<double, 3>{5.5, 2, 2.4});
  CHECK(v.density == 12);
  CHECK(v.density_model == 370);
  CHECK(v.heading_ambiguity == 180);
  CHECK(v.nearest_instance == "van-1");
  CHECK(v.class_score == 0.9);
  // The measured rectangle (collect --size-only reads it).
  CHECK(v.measured_size == std::array<double, 3>{5.4, 1.9, 2.35});
  CHECK(v.measured_centre == std::array<double, 2>{0.25, -0.5});
  CHECK(v.measured_heading == 89.5);
  CHECK(v.measured_edge_correction == 0.03);
  // A malformed one is refused naming the member.
  Json bad = j;
  bad["measured"]["size"] = Json::array({5.4, -1, 2});
  CHECK_THROWS_WITH(documents::parse_verdict(bad.dump(), "class.json"), Catch::Contains("measured.size"));
  bad["measured"] = Json{{"size", {5.4, 1.9, 2.35}}, {"centre", {0.25}}, {"heading_deg", 0}};
  CHECK_THROWS_WITH(documents::parse_verdict(bad.dump(), "class.json"), Catch::Contains("measured.centre"));
  bad["measured"] = "wide";
  CHECK_THROWS_WITH(documents::parse_verdict(bad.dump(), "class.json"), Catch::Contains("measured must be"));
  c.confidence = std::nan("");
  CHECK_THROWS_WITH(documents::serialize_class_verdict(c), Catch::Contains("non-finite confidence"));
}

TEST_CASE("classification: refused_on, what a none rests on, is the last member and only on a none") {
  documents::ClassVerdict c = measured(old_output::kClassifyTank);
  CHECK(Json::parse(documents::serialize_class_verdict(c)).contains("refused_on") == false);  // a class
  c.cls = c.group = "";
  c.pose.reset();
  c.pose_tile.reset();
  c.size.reset();
  c.reason = "not_vehicle_shape";
  c.detail = "a flat box";
  c.refused_on = "shape";
  const std::string text = documents::serialize_class_verdict(c);
  const Json j = Json::parse(text);
  CHECK(j.back() == "shape");
  CHECK(std::prev(j.end()).key() == "refused_on");
  const documents::Verdict v = documents::parse_verdict(text, "class.json");
  CHECK(v.reason == "not_vehicle_shape");
  CHECK(v.refused_on == "shape");
  Json bad = j;
  bad["refused_on"] = "colour";
  CHECK_THROWS_WITH(documents::parse_verdict(bad.dump(), "class.json"),
                    Catch::Contains("refused_on must be density, surface, size, shape or null"));
  bad.erase("refused_on");  // older documents: unsaid
  CHECK(documents::parse_verdict(bad.dump(), "class.json").refused_on.empty());
}
