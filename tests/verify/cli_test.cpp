// The verify binary: a verdict from a match result, points, segments and a modelbase; bad
// input exits 1 naming the file and leaves no output; the verdict reads back.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "canopy/common/math.h"
#include "canopy/common/atomic_file.h"
#include "canopy/formats/match_result.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/segment_graph.h"
#include "canopy/formats/verdict.h"
#include "fixtures.h"
#include "support/cli.h"

namespace fs = std::filesystem;
namespace fm = canopy::formats;
using namespace verify_test;
using canopy::test::sh;

namespace {

const std::string kBin = std::string(CANOPY_BIN_DIR) + "/verify";

fm::PointCloud surface_cloud(const canopy::verify::Surface& s) {
  canopy::verify::Candidate c{s.points, s.normals, std::vector<Vector3d>(s.points.size(), Vector3d::UnitZ())};
  return to_cloud(c);
}

struct Case {
  fs::path dir, mb, match, points, segments;
  explicit Case(const std::string& name) {
    dir = canopy::test::fresh_dir("verify", name);
    mb = dir / "mb";
    fs::create_directories(mb);
    fm::write_segment_graph(graph(pickup()), (mb / "pickup.json").string());
    fm::write_pcd(surface_cloud(sample(pickup(), 0.1)), (mb / "pickup.pcd").string());
    fm::write_segment_graph(graph(flatbed()), (mb / "flatbed.json").string());
    fm::write_pcd(surface_cloud(sample(flatbed(), 0.1)), (mb / "flatbed.pcd").string());
    const Isometry3d T = pose(1.0, 2.0, -1.0);
    match = dir / "match.json";
    points = dir / "samples.pcd";
    segments = dir / "segments.json";
    fm::write_match_result(match_of({"flatbed", "pickup"}), match.string());
    fm::write_pcd(to_cloud(candidate(sample(pickup(), 0.1, 0.05), pickup(), T)), points.string());
    fm::write_segment_graph(posed(graph(pickup()), T), segments.string());
  }
  static fm::MatchResult match_of(const std::vector<std::string>& names) {
    std::vector<fm::SegmentGraph> gs;
    for (const auto& n : names) gs.push_back(n == "pickup" ? graph(pickup()) : graph(flatbed()));
    return verify_test::match(names, gs, false);
  }
  std::string cmd(const fs::path& out) const {
    return kBin + " -i " + match.string() + " --points " + points.string() + " --segments " +
           segments.string() + " --modelbase " + mb.string() + " -o " + out.string();
  }
};

}  // namespace

TEST_CASE("verify answers the right model with its pose, byte-identical on reruns", "[verify][cli]") {
  const Case c("ok");
  std::string err;
  REQUIRE(sh(c.cmd(c.dir / "a.json"), c.dir / "err", &err) == 0);
  REQUIRE(err.find("check: pickup, confidence") != std::string::npos);
  REQUIRE(sh(c.cmd(c.dir / "b.json"), c.dir / "err", &err) == 0);
  REQUIRE(canopy::common::read_file((c.dir / "a.json").string()) ==
          canopy::common::read_file((c.dir / "b.json").string()));
  const fm::Verdict v = fm::read_verdict((c.dir / "a.json").string());
  REQUIRE(v.model == "pickup");
  REQUIRE(v.hypotheses.size() == 2);
  REQUIRE(v.hypotheses[0].model == "flatbed");
  REQUIRE(v.chosen == 1);
  const auto e = fm::euler_degrees(v.hypotheses[1].pose);
  CHECK(e[0] == Approx(1.0 * 180 / canopy::common::kPi).margin(0.1));
  CHECK(v.hypotheses[1].pose.translation[0] == Approx(2.0).margin(1e-3));
  CHECK(v.hypotheses[1].pose.translation[1] == Approx(-1.0).margin(1e-3));
  CHECK(!v.transform);
  CHECK(!v.hypotheses[1].pose_tile);

  // A tile transform (float64, far from the origin) adds the pose in tile coordinates.
  REQUIRE(sh(c.cmd(c.dir / "t.json") + " --transform 1,0,0,500000.25,0,1,0,4400000.5,0,0,1,12", c.dir / "err",
             &err) == 0);
  const fm::Verdict t = fm::read_verdict((c.dir / "t.json").string());
  REQUIRE(t.hypotheses[1].pose_tile);
  CHECK(t.hypotheses[1].pose_tile->translation[0] == Approx(500002.25).epsilon(0).margin(1e-3));
  CHECK(t.hypotheses[1].pose_tile->translation[1] == Approx(4399999.5).epsilon(0).margin(1e-3));
  CHECK(t.hypotheses[1].pose_tile->translation[2] ==
        Approx(12 + v.hypotheses[1].pose.translation[2]).margin(1e-9));
  // The shipped defaults are accepted as a config file.
  REQUIRE(sh(c.cmd(c.dir / "c.json") + " --config " + CANOPY_SOURCE_DIR + "/share/params/verify.ini",
             c.dir / "err", &err) == 0);
  REQUIRE(sh(c.cmd(c.dir / "u.json") + " --transform 1,2,3", c.dir / "err", &err) == 2);
}

TEST_CASE("a modelbase with classes: the verdict names the class and the nearest instance", "[verify][cli]") {
  const Case c("classes");
  std::string err;
  REQUIRE(sh(c.cmd(c.dir / "plain.json"), c.dir / "err", &err) == 0);
  const std::string plain = canopy::common::read_file((c.dir / "plain.json").string());
  CHECK(plain.find("\"class\"") == std::string::npos);  // no classes: no class keys
  CHECK(plain.find("nearest_instance") == std::string::npos);

  canopy::common::write_file_atomic((c.mb / "pickup.class").string(), "light-truck\n");
  canopy::common::write_file_atomic((c.mb / "flatbed.class").string(), "heavy-truck\n");
  REQUIRE(sh(c.cmd(c.dir / "cls.json"), c.dir / "err", &err) == 0);
  CHECK(err.find("class light-truck (nearest instance pickup") != std::string::npos);
  const fm::Verdict v = fm::read_verdict((c.dir / "cls.json").string());
  REQUIRE(v.has_classes);
  CHECK(v.vehicle_class == "light-truck");
  CHECK(v.nearest_instance == "pickup");
  CHECK(v.model == "pickup");
  CHECK(v.class_score == Approx(v.hypotheses[1].score).margin(1e-12));
  CHECK(v.class_margin == Approx(v.hypotheses[1].score - v.hypotheses[0].score).margin(1e-12));
  CHECK(v.hypotheses[0].vehicle_class == "heavy-truck");
  CHECK(v.hypotheses[1].vehicle_class == "light-truck");
  // Everything else is as without classes, and the document round-trips.
  fm::Verdict stripped = v;
  stripped.has_classes = false;
  stripped.provenance = fm::read_verdict((c.dir / "plain.json").string()).provenance;
  for (auto& h : stripped.hypotheses) h.vehicle_class.clear();
  CHECK(fm::serialize_verdict(stripped) == plain);
  CHECK(fm::serialize_verdict(fm::parse_verdict(fm::serialize_verdict(v), "x")) == fm::serialize_verdict(v));

  // Both hypotheses of one class: the margin over another class is the whole score.
  canopy::common::write_file_atomic((c.mb / "flatbed.class").string(), "light-truck");
  REQUIRE(sh(c.cmd(c.dir / "same.json"), c.dir / "err", &err) == 0);
  const fm::Verdict s = fm::read_verdict((c.dir / "same.json").string());
  CHECK(s.vehicle_class == "light-truck");
  CHECK(s.class_margin == Approx(s.class_score).margin(1e-12));

  // A malformed class file is an error naming it, without output.
  canopy::common::write_file_atomic((c.mb / "flatbed.class").string(), "two words\n");
  REQUIRE(sh(c.cmd(c.dir / "bad.json"), c.dir / "err", &err) == 1);
  CHECK(err.find((c.mb / "flatbed.class").string()) != std::string::npos);
  CHECK(!fs::exists(c.dir / "bad.json"));
}

TEST_CASE("bad input exits 1 naming the file, no output", "[verify][cli]") {
  std::string err;
  SECTION("a hypothesis naming a model not in the modelbase") {
    const Case c("ghost");
    fm::write_match_result(Case::match_of({"pickup"}), c.match.string());
    auto m = fm::read_match_result(c.match.string());
    m.models[0].model = "ghost";
    fm::write_match_result(m, c.match.string());
    REQUIRE(sh(c.cmd(c.dir / "v.json"), c.dir / "err", &err) == 1);
    CHECK(err.find(c.match.string()) != std::string::npos);
    CHECK(err.find("ghost") != std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
  }
  SECTION("points without normals") {
    const Case c("nonormals");
    fm::write_pcd(to_cloud(candidate(sample(pickup(), 0.2), pickup(), pose(0, 0, 0)), false),
                  c.points.string());
    REQUIRE(sh(c.cmd(c.dir / "v.json"), c.dir / "err", &err) == 1);
    CHECK(err.find(c.points.string()) != std::string::npos);
    CHECK(err.find("normal") != std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
  }
  SECTION("an empty candidate") {
    const Case c("empty");
    fm::PointCloud none;
    for (const char* f :
         {"x", "y", "z", "normal_x", "normal_y", "normal_z", "sensor_x", "sensor_y", "sensor_z"}) {
      none.add(f);
    }
    fm::write_pcd(none, c.points.string());
    REQUIRE(sh(c.cmd(c.dir / "v.json"), c.dir / "err", &err) == 1);
    CHECK(err.find(c.points.string()) != std::string::npos);
    CHECK(err.find("empty") != std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
  }
  SECTION("a modelbase entry without its surface") {
    const Case c("nosurface");
    fs::remove(c.mb / "flatbed.pcd");
    REQUIRE(sh(c.cmd(c.dir / "v.json"), c.dir / "err", &err) == 1);
    CHECK(err.find((c.mb / "flatbed.pcd").string()) != std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
  }
}

TEST_CASE("verdict documents round-trip and reject bad versions", "[verify][formats]") {
  fm::Verdict v;
  v.provenance = {"verify", "0.1.0", {{"top-k", "3"}}, {"m.json", "s.pcd"}};
  v.candidate = "s.pcd";
  fm::Hypothesis h;
  h.model = "sedan";
  h.gmatch_rank = 1;
  h.gmatch_score = 0.61;
  h.start = "pairs";
  h.pose.rotation = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  h.pose.translation = {1.5, -2.25, 0.01};
  h.pose_tile = fm::Pose{{0, -1, 0, 1, 0, 0, 0, 0, 1}, {500001.5, 4400000.125, 12.01}};
  h.fit_rms = 0.012;
  h.explained = 0.91;
  h.free_space_violation = 0.02;
  h.score = 0.8918;
  h.flip_score = 0.3;
  v.hypotheses = {h};
  v.chosen = 0;
  v.model = "sedan";
  v.confidence = 0.97;
  const std::string text = fm::serialize_verdict(v);
  const fm::Verdict r = fm::parse_verdict(text, "v.json");
  REQUIRE(fm::serialize_verdict(r) == text);
  REQUIRE(r.hypotheses[0].pose_tile->translation[1] == 4400000.125);
  REQUIRE(fm::euler_degrees(r.hypotheses[0].pose)[0] == Approx(90));
  std::string bad = text;
  bad.replace(bad.find("\"version\": 1"), 12, "\"version\": 2");
  REQUIRE_THROWS_WITH(fm::parse_verdict(bad, "v.json"),
                      Catch::Contains("v.json") && Catch::Contains("version"));
  REQUIRE_THROWS_WITH(fm::parse_verdict("{\"format\": \"canopy.match_result\", \"version\": 1}", "w.json"),
                      Catch::Contains("w.json") && Catch::Contains("canopy.verdict"));
}
