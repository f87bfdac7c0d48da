// The verify binary: a verdict from a match result, points, segments and a modelbase; bad
// input exits 1 naming the file and leaves no output; the verdict reads back.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <string>

#include "canopy/common/math.h"
#include "canopy/common/atomic_file.h"
#include "canopy/documents/match_result.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"
#include "canopy/documents/segment_graph.h"
#include "canopy/documents/verdict.h"
#include "fixtures.h"
#include "support/cli.h"

namespace fs = std::filesystem;
namespace doc = canopy::documents;
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
    doc::write_segment_graph(graph(pickup()), (mb / "pickup.json").string());
    fm::write_pcd(surface_cloud(sample(pickup(), 0.1)), (mb / "pickup.pcd").string());
    doc::write_segment_graph(graph(flatbed()), (mb / "flatbed.json").string());
    fm::write_pcd(surface_cloud(sample(flatbed(), 0.1)), (mb / "flatbed.pcd").string());
    const Isometry3d T = pose(1.0, 2.0, -1.0);
    match = dir / "match.json";
    points = dir / "samples.pcd";
    segments = dir / "segments.json";
    doc::write_match_result(match_of({"flatbed", "pickup"}), match.string());
    fm::write_pcd(to_cloud(candidate(sample(pickup(), 0.1, 0.05), pickup(), T)), points.string());
    doc::write_segment_graph(posed(seen(graph(pickup())), T), segments.string());
  }
  // The object's graph as a scan gives it: no bottom faces (the matches pair every other face).
  static doc::SegmentGraph seen(doc::SegmentGraph g) {
    g.segments.erase(std::remove_if(g.segments.begin(), g.segments.end(),
                                    [](const doc::Segment& s) { return s.normal[2] < -0.5; }),
                     g.segments.end());
    return g;
  }
  static doc::MatchResult match_of(const std::vector<std::string>& names) {
    return match_for(seen(graph(pickup())), names);
  }
  // A match of `object` as gmatch writes it: every model pairs the object's segments, largest
  // first (here all NULL: the pose comes from the principal axes).
  static doc::MatchResult match_for(const doc::SegmentGraph& object, const std::vector<std::string>& names) {
    doc::MatchResult r;
    r.provenance = {"test", "0", {}, {}};
    r.object = "segments.json";
    r.error_form = "bounded";
    std::vector<doc::Segment> by_area = object.segments;
    std::stable_sort(by_area.begin(), by_area.end(), [](const doc::Segment& a, const doc::Segment& b) {
      return a.area != b.area ? a.area > b.area : a.segment_id < b.segment_id;
    });
    for (std::size_t i = 0; i < names.size(); ++i) {
      doc::ModelScore m;
      m.model = names[i];
      m.rank = static_cast<int>(i + 1);
      m.score = 0.5 - 0.1 * static_cast<double>(i);
      for (const auto& s : by_area) m.pairs.push_back({s.segment_id, -1, 0.0});
      r.models.push_back(m);
    }
    return r;
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
  const canopy::documents::Verdict v = canopy::documents::read_verdict((c.dir / "a.json").string());
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
  const canopy::documents::Verdict t = canopy::documents::read_verdict((c.dir / "t.json").string());
  REQUIRE(t.hypotheses[1].pose_tile);
  CHECK(t.hypotheses[1].pose_tile->translation[0] == Approx(500002.25).epsilon(0).margin(1e-3));
  CHECK(t.hypotheses[1].pose_tile->translation[1] == Approx(4399999.5).epsilon(0).margin(1e-3));
  CHECK(t.hypotheses[1].pose_tile->translation[2] ==
        Approx(12 + v.hypotheses[1].pose.translation[2]).margin(1e-9));
  // The shipped defaults are accepted as a config file.
  REQUIRE(sh(c.cmd(c.dir / "c.json") + " --config " + CANOPY_SOURCE_DIR + "/share/params/verify.ini",
             c.dir / "err", &err) == 0);
  REQUIRE(sh(c.cmd(c.dir / "u.json") + " --transform 1,2,3", c.dir / "err", &err) == 2);
  // A 4x4 is read row-major: its fourth row must be 0,0,0,1 (a column-major matrix, whose
  // translation is its fourth row, is refused instead of losing the translation: review F15).
  REQUIRE(sh(c.cmd(c.dir / "r.json") + " --transform 1,0,0,2,0,1,0,3,0,0,1,4,0,0,0,1", c.dir / "err", &err) ==
          0);
  CHECK(sh(c.cmd(c.dir / "col.json") + " --transform 1,0,0,0,0,1,0,0,0,0,1,0,2,3,4,1", c.dir / "err", &err) ==
        2);
  CHECK(err.find("fourth row") != std::string::npos);
  CHECK(err.find("column-major") != std::string::npos);
  CHECK_FALSE(fs::exists(c.dir / "col.json"));
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
  const canopy::documents::Verdict v = canopy::documents::read_verdict((c.dir / "cls.json").string());
  REQUIRE(v.has_classes);
  CHECK(v.vehicle_class == "light-truck");
  CHECK(v.nearest_instance == "pickup");
  CHECK(v.model == "pickup");
  CHECK(v.class_score == Approx(v.hypotheses[1].score).margin(1e-12));
  CHECK(v.class_margin == Approx(v.hypotheses[1].score - v.hypotheses[0].score).margin(1e-12));
  CHECK(v.hypotheses[0].vehicle_class == "heavy-truck");
  CHECK(v.hypotheses[1].vehicle_class == "light-truck");
  // Everything else is as without classes, and the document round-trips.
  canopy::documents::Verdict stripped = v;
  stripped.has_classes = false;
  stripped.provenance = canopy::documents::read_verdict((c.dir / "plain.json").string()).provenance;
  for (auto& h : stripped.hypotheses) h.vehicle_class.clear();
  CHECK(canopy::documents::serialize_verdict(stripped) == plain);
  CHECK(canopy::documents::serialize_verdict(canopy::documents::parse_verdict(
            canopy::documents::serialize_verdict(v), "x")) == canopy::documents::serialize_verdict(v));

  // Both hypotheses of one class: the margin over another class is the whole score.
  canopy::common::write_file_atomic((c.mb / "flatbed.class").string(), "light-truck");
  REQUIRE(sh(c.cmd(c.dir / "same.json"), c.dir / "err", &err) == 0);
  const canopy::documents::Verdict s = canopy::documents::read_verdict((c.dir / "same.json").string());
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
    doc::write_match_result(Case::match_of({"pickup"}), c.match.string());
    auto m = doc::read_match_result(c.match.string());
    m.models[0].model = "ghost";
    doc::write_match_result(m, c.match.string());
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
  canopy::documents::Verdict v;
  v.provenance = {"verify", "0.1.0", {{"top-k", "3"}}, {"m.json", "s.pcd"}};
  v.candidate = "s.pcd";
  canopy::documents::Hypothesis h;
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
  const std::string text = canopy::documents::serialize_verdict(v);
  const canopy::documents::Verdict r = canopy::documents::parse_verdict(text, "v.json");
  REQUIRE(canopy::documents::serialize_verdict(r) == text);
  REQUIRE(r.hypotheses[0].pose_tile->translation[1] == 4400000.125);
  REQUIRE(fm::euler_degrees(r.hypotheses[0].pose)[0] == Approx(90));
  std::string bad = text;
  bad.replace(bad.find("\"version\": 1"), 12, "\"version\": 2");
  REQUIRE_THROWS_WITH(canopy::documents::parse_verdict(bad, "v.json"),
                      Catch::Contains("v.json") && Catch::Contains("version"));
  REQUIRE_THROWS_WITH(
      canopy::documents::parse_verdict("{\"format\": \"canopy.match_result\", \"version\": 1}", "w.json"),
      Catch::Contains("w.json") && Catch::Contains("canopy.verdict"));
}

namespace {

// A 6 x 6 grid mesh 5 cm apart at z = 1 (every other column 2 cm higher): the foreign mesh of
// the round-3 reproducer (../shared/data/malformed/round3/verify/other-mesh-grid-6x6.ply).
fm::Mesh grid_mesh() {
  fm::Mesh m;
  m.vertices.resize(36);
  auto& x = m.vertices.add("x");
  auto& y = m.vertices.add("y");
  auto& z = m.vertices.add("z");
  for (int j = 0; j < 6; ++j) {
    for (int i = 0; i < 6; ++i) {
      x[6 * j + i] = 0.05 * i;
      y[6 * j + i] = 0.05 * j;
      z[6 * j + i] = i % 2 ? 1.02 : 1.0;
    }
  }
  for (int j = 0; j < 5; ++j) {
    for (int i = 0; i < 5; ++i) {
      const int a = 6 * j + i;
      m.faces.push_back({a, a + 1, a + 7});
      m.faces.push_back({a, a + 7, a + 6});
    }
  }
  return m;
}

// A mesh of every other row of the candidate's points as verify reads them (cocone keeps
// sample rows as they are), and the Case's graph made to index it: segment k holds vertices
// 10 k ... 10 k + 9.
void mesh_of_points(const Case& c, const fs::path& points, const fs::path& mesh_path,
                    const fs::path& graph_path) {
  const fm::PointCloud pc = fm::read_pcd(points.string());
  doc::SegmentGraph g = doc::read_segment_graph(c.segments.string());
  const int n = static_cast<int>(10 * g.segments.size());
  REQUIRE(static_cast<int>(pc.size()) >= 2 * n);
  fm::Mesh m;
  m.vertices.resize(n);
  for (const char* f : {"x", "y", "z"}) {
    auto& col = m.vertices.add(f, pc.type(f));
    for (int i = 0; i < n; ++i) col[i] = pc.col(f)[2 * i];
  }
  for (int i = 0; i + 2 < n; i += 3) m.faces.push_back({i, i + 1, i + 2});
  fm::write_ply(m, mesh_path.string());
  g.mesh = mesh_path.string();
  for (std::size_t k = 0; k < g.segments.size(); ++k) {
    g.segments[k].vertices.clear();
    for (int v = 0; v < 10; ++v) g.segments[k].vertices.push_back(static_cast<int>(10 * k) + v);
  }
  doc::write_segment_graph(g, graph_path.string());
}

std::string with(const Case& c, const fs::path& match, const fs::path& points, const fs::path& segments,
                 const fs::path& out) {
  return kBin + " -i " + match.string() + " --points " + points.string() + " --segments " +
         segments.string() + " --modelbase " + c.mb.string() + " -o " + out.string();
}

}  // namespace

TEST_CASE("inputs that belong together are accepted, the verdict unchanged by the check", "[verify][cli]") {
  const Case c("belong_ok");
  std::string err;
  REQUIRE(sh(c.cmd(c.dir / "plain.json"), c.dir / "err", &err) == 0);
  // The graph names its mesh, whose vertices are rows of the points: the mesh check runs and
  // passes; the verdict is byte for byte the one without it (the graph's statistics are equal).
  mesh_of_points(c, c.points, c.dir / "mesh.ply", c.segments);
  REQUIRE(doc::read_segment_graph(c.segments.string()).mesh == (c.dir / "mesh.ply").string());
  REQUIRE(sh(c.cmd(c.dir / "m.json") + " -v", c.dir / "err", &err) == 0);
  CHECK(err.find("not checked against") == std::string::npos);
  CHECK(canopy::common::read_file((c.dir / "m.json").string()) ==
        canopy::common::read_file((c.dir / "plain.json").string()));
  // The match read from stdin, and a match whose "object" is spelled differently but is the
  // same file, are accepted.
  REQUIRE(sh("cat " + c.match.string() + " | " + with(c, "-", c.points, c.segments, c.dir / "s.json"),
             c.dir / "err", &err) == 0);
  auto m = doc::read_match_result(c.match.string());
  m.object = (c.dir / "." / "segments.json").string();
  doc::write_match_result(m, (c.dir / "match-abs.json").string());
  REQUIRE(sh(with(c, c.dir / "match-abs.json", c.points, c.segments, c.dir / "a.json"), c.dir / "err", &err) ==
          0);
}

TEST_CASE("inputs that do not belong together are refused naming the files (round 3, case 12)",
          "[verify][cli]") {
  std::string err;
  SECTION("the segment graph of another mesh (the replay: ncut on a 6 x 6 grid)") {
    const Case c("belong_grid");
    fm::write_ply(grid_mesh(), (c.dir / "other-mesh-grid-6x6.ply").string());
    REQUIRE(sh(std::string(CANOPY_BIN_DIR) + "/ncut -q -i " + (c.dir / "other-mesh-grid-6x6.ply").string() +
                   " -o " + (c.dir / "other-seg.json").string(),
               c.dir / "err", &err) == 0);
    REQUIRE(sh(with(c, c.match, c.points, c.dir / "other-seg.json", c.dir / "v.json"), c.dir / "err", &err) ==
            1);
    CHECK(err.find(c.match.string()) != std::string::npos);  // made from segments.json, beside it
    CHECK(err.find((c.dir / "other-seg.json").string()) != std::string::npos);
    CHECK(err.find("was made from the segment graph segments.json") != std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
    // With the match's "object" unresolvable, its pairs name segments the grid's graph lacks.
    auto m = doc::read_match_result(c.match.string());
    m.object = "gone/segments.json";
    doc::write_match_result(m, (c.dir / "m2.json").string());
    REQUIRE(sh(with(c, c.dir / "m2.json", c.points, c.dir / "other-seg.json", c.dir / "v.json"),
               c.dir / "err", &err) == 1);
    CHECK(err.find((c.dir / "m2.json").string() + ": models[0] (flatbed) pairs") != std::string::npos);
    CHECK(err.find("another segment graph") != std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
  }
  SECTION("a graph whose mesh is another mesh: a vertex that is not one of the points") {
    const Case c("belong_mesh");
    fm::write_ply(grid_mesh(), (c.dir / "grid.ply").string());
    doc::SegmentGraph g = doc::read_segment_graph(c.segments.string());
    g.mesh = (c.dir / "grid.ply").string();
    for (auto& s : g.segments) s.vertex_count = 0;
    g.segments[0].vertex_count = 36;
    doc::write_segment_graph(g, (c.dir / "seg.json").string());
    auto m = doc::read_match_result(c.match.string());
    m.object = "seg.json";
    doc::write_match_result(m, (c.dir / "m.json").string());
    REQUIRE(sh(with(c, c.dir / "m.json", c.points, c.dir / "seg.json", c.dir / "v.json"), c.dir / "err",
               &err) == 1);
    CHECK(err.find((c.dir / "seg.json").string() + ": its mesh " + (c.dir / "grid.ply").string() +
                   " has vertex 0 at (0, 0, 1), which is not a point of " + c.points.string()) !=
          std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
  }
  SECTION("another candidate's points") {
    const Case c("belong_points");
    // Its own mesh is rows of its own points; the other candidate is the same pickup sampled
    // 5 cm apart elsewhere: same shape, same box, other points.
    mesh_of_points(c, c.points, c.dir / "mesh.ply", c.dir / "seg.json");
    auto m = doc::read_match_result(c.match.string());
    m.object = "seg.json";
    doc::write_match_result(m, (c.dir / "m.json").string());
    const fs::path other = c.dir / "other.pcd";
    fm::write_pcd(to_cloud(candidate(sample(pickup(), 0.1, 0.0), pickup(), pose(1.0, 2.0, -1.0))),
                  other.string());
    REQUIRE(sh(with(c, c.dir / "m.json", other, c.dir / "seg.json", c.dir / "v.json"), c.dir / "err", &err) ==
            1);
    CHECK(err.find("is not a point of " + other.string()) != std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
    // Without the mesh at hand, a smaller candidate's points are refused by their box: the
    // pickup's cabin roof (z = 1.7 m) is above every point of a 0.8 m high box.
    const std::vector<Box> low{{{-1, -0.5, 0.3}, {1, 0.5, 0.8}}};
    fm::write_pcd(to_cloud(candidate(sample(low, 0.1), low, pose(1.0, 2.0, -1.0))), other.string());
    REQUIRE(sh(with(c, c.match, other, c.segments, c.dir / "v.json"), c.dir / "err", &err) == 1);
    CHECK(err.find(c.segments.string() + ": segment ") != std::string::npos);
    CHECK(err.find("outside the box of " + other.string()) != std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
  }
  SECTION("the match of another object") {
    const Case c("belong_match");
    fs::create_directories(c.dir / "other");
    doc::write_segment_graph(posed(Case::seen(graph(flatbed())), pose(0, 0, 0)),
                             (c.dir / "other" / "segments.json").string());
    const doc::MatchResult m = Case::match_for(Case::seen(graph(flatbed())), {"flatbed", "pickup"});
    doc::write_match_result(m, (c.dir / "other" / "match.json").string());
    REQUIRE(sh(with(c, c.dir / "other" / "match.json", c.points, c.segments, c.dir / "v.json"), c.dir / "err",
               &err) == 1);
    CHECK(err.find((c.dir / "other" / "match.json").string() +
                   ": was made from the segment graph segments.json, "
                   "not from " +
                   c.segments.string()) != std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
    // Its "object" gone, the pairs give it away: segment 17 (the flatbed's crate roof) is not ours.
    fs::remove(c.dir / "other" / "segments.json");
    REQUIRE(sh(with(c, c.dir / "other" / "match.json", c.points, c.segments, c.dir / "v.json"), c.dir / "err",
               &err) == 1);
    CHECK(err.find("pairs object segment 17, which " + c.segments.string() + " does not have") !=
          std::string::npos);
    CHECK(!fs::exists(c.dir / "v.json"));
  }
}

TEST_CASE("bounded options: --icp-iterations, --transform decimal only (round 3, case 16)", "[verify][cli]") {
  const Case c("bounds");
  std::string err;
  REQUIRE(sh(c.cmd(c.dir / "v.json") + " --icp-iterations 2147483647", c.dir / "err", &err) == 2);
  CHECK(err.find("--icp-iterations must be in [0, 500]") != std::string::npos);
  REQUIRE(sh(c.cmd(c.dir / "v.json") + " --icp-iterations 501", c.dir / "err", &err) == 2);
  REQUIRE(sh(c.cmd(c.dir / "v.json") + " --transform 0x1p0,0,0,0,0,1,0,0,0,0,1,0", c.dir / "err", &err) == 2);
  CHECK(err.find("'0x1p0' is not a decimal number") != std::string::npos);
  REQUIRE(sh(c.cmd(c.dir / "v.json") + " --transform 1,0,0,inf,0,1,0,0,0,0,1,0", c.dir / "err", &err) == 2);
  CHECK(!fs::exists(c.dir / "v.json"));
  REQUIRE(sh(c.cmd(c.dir / "v.json") + " --icp-iterations 500 --transform 1,0,0,0,0,1,0,0,0,0,1,0",
             c.dir / "err", &err) == 0);
}

TEST_CASE("a hypothesis whose model is a path is refused before the modelbase is read", "[verify][cli]") {
  const Case c("pathmodel");
  std::string err;
  auto m = doc::read_match_result(c.match.string());
  m.models[0].model = "../mb/flatbed";
  doc::write_match_result(m, c.match.string());
  REQUIRE(sh(c.cmd(c.dir / "v.json"), c.dir / "err", &err) == 1);
  CHECK(err.find(c.match.string() + ": hypothesis names model '../mb/flatbed', which is not a model name") !=
        std::string::npos);
  CHECK(!fs::exists(c.dir / "v.json"));
}

TEST_CASE("the verdict reader types every member and never casts a number to int", "[verify][formats]") {
  canopy::documents::Verdict v;
  v.provenance = {"verify", "0.1.0", {{"top-k", "3"}}, {"m.json", "s.pcd"}};
  v.candidate = "s.pcd";
  canopy::documents::Hypothesis h;
  h.model = "sedan";
  h.gmatch_rank = 1;
  h.start = "pairs";
  v.hypotheses = {h};
  v.chosen = 0;
  v.model = "sedan";
  v.confidence = 0.5;
  v.has_classes = true;
  v.vehicle_class = "car";
  v.nearest_instance = "sedan";
  const std::string text = canopy::documents::serialize_verdict(v);
  REQUIRE(canopy::documents::serialize_verdict(canopy::documents::parse_verdict(text, "v.json")) == text);
  auto edited = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const auto at = t.find(from);
    REQUIRE(at != std::string::npos);
    return t.replace(at, from.size(), to);
  };
  struct Bad {
    std::string from, to, why;
  };
  for (const auto& b : std::vector<Bad>{
           {"\"gmatch_rank\": 1", "\"gmatch_rank\": 1.5",
            "hypotheses[0].gmatch_rank must be an integer in [1, "},
           {"\"gmatch_rank\": 1", "\"gmatch_rank\": 1e30", "hypotheses[0].gmatch_rank must be an integer"},
           {"\"gmatch_rank\": 1", "\"gmatch_rank\": 0", "hypotheses[0].gmatch_rank must be an integer"},
           {"\"chosen\": 0", "\"chosen\": 0.0", "chosen must be an integer in [-1, "},
           {"\"chosen\": 0", "\"chosen\": -2", "chosen must be an integer"},
           {"\"chosen\": 0", "\"chosen\": 4294967296", "chosen must be an integer"},
           {"\"chosen\": 0", "\"chosen\": 1", "chosen is not -1 or a hypothesis index"},
           {"\"model\": \"sedan\",\n \"confidence\"", "\"model\": \"../sedan\",\n \"confidence\"",
            "model must be a model name"},
           {"\"nearest_instance\": \"sedan\"", "\"nearest_instance\": \"a/b\"",
            "nearest_instance must be a model name"},
           {"\"class\": \"car\"", "\"class\": 7", "class must be a model name"},
           {"\"confidence\": 0.5", "\"confidence\": \"0.5\"", "confidence must be a number, not \"0.5\""},
           {"\"flipped\": false", "\"flipped\": 0", "hypotheses[0].flipped must be true or false, not 0"},
           {"\"candidate\": \"s.pcd\"", "\"candidate\": null", "candidate must be a string, not null"},
           {"\"hypotheses\": [", "\"hypotheses\": [3, ", "hypotheses[0] must be an object, not 3"},
           {"\"transform\": null", "\"transform\": {\"matrix\": [1, 2]}",
            "transform.matrix must be 16 numbers"},
           {"\"transform\": null", "\"transform\": 5", "transform must be an object, not 5"},
       }) {
    INFO(b.to);
    CHECK_THROWS_WITH(canopy::documents::parse_verdict(edited(b.from, b.to), "v.json"),
                      Catch::StartsWith("v.json: malformed verdict: " + b.why));
  }
}

TEST_CASE("sensor directions from what LAS has (issue 26): columns unchanged, derived sources, refusals",
          "[verify][cli]") {
  const Case c("sensordir");
  std::string err;
  // With sensor_x/y/z the default and an explicit auto write the same bytes (the simulator's path).
  REQUIRE(sh(c.cmd(c.dir / "a.json"), c.dir / "err", &err) == 0);
  REQUIRE(sh(c.cmd(c.dir / "b.json") + " --sensor-direction auto --trajectory-tolerance 1", c.dir / "err",
             &err) == 0);
  CHECK(canopy::common::read_file((c.dir / "a.json").string()) ==
        canopy::common::read_file((c.dir / "b.json").string()));

  // The same points as a LAS-derived candidate: no sensor columns, a GPS time per point.
  fm::PointCloud las = fm::read_pcd(c.points.string());
  for (const char* f : {"sensor_x", "sensor_y", "sensor_z"}) las.remove(f);
  las.add("gps_time", fm::kFloat64).assign(las.size(), 5.0);
  const fs::path points = c.dir / "las.pcd";
  fm::write_pcd(las, points.string());
  const std::string cmd = kBin + " -i " + c.match.string() + " --points " + points.string() + " --segments " +
                          c.segments.string() + " --modelbase " + c.mb.string();

  // Nothing but gps_time: the vertical, with a warning naming the points.
  REQUIRE(sh(cmd + " -o " + (c.dir / "v.json").string(), c.dir / "err", &err) == 0);
  CHECK(err.find("warning: " + points.string() + ": no sensor_x/y/z") != std::string::npos);
  CHECK(err.find("vertical") != std::string::npos);
  // Options at their defaults stay out of the provenance.
  for (const auto& kv : canopy::documents::read_verdict((c.dir / "v.json").string()).provenance.parameters) {
    CHECK(kv.first.find("sensor") == std::string::npos);
    CHECK(kv.first.find("trajectory") == std::string::npos);
  }

  // A trajectory straight above: the sensor at (0, 0, 300) at t = 5.
  const fs::path traj = c.dir / "traj.txt";
  canopy::common::write_file_atomic(traj.string(),
                                    "# canopy trajectory 1\ntime x y z roll pitch heading\n"
                                    "0 -50 0 300 0 0 0\n10 50 0 300 0 0 0\n");
  REQUIRE(sh(cmd + " --trajectory " + traj.string() + " -o " + (c.dir / "t.json").string(), c.dir / "err",
             &err) == 0);
  CHECK(err.find("warning") == std::string::npos);
  CHECK(err.find("sensor directions from the trajectory " + traj.string()) != std::string::npos);
  const canopy::documents::Verdict t = canopy::documents::read_verdict((c.dir / "t.json").string());
  CHECK(t.provenance.inputs.back() == traj.string());
  CHECK(t.model == "pickup");

  // Refusals: exit 1 naming the file (and the line), exit 2 for a usage error; no output.
  REQUIRE(sh(cmd + " --sensor-direction columns -o " + (c.dir / "x.json").string(), c.dir / "err", &err) == 1);
  CHECK(err.find(points.string() + ": field 'sensor_x' missing") != std::string::npos);
  REQUIRE(sh(cmd + " --sensor-direction scan-angle -o " + (c.dir / "x.json").string(), c.dir / "err", &err) ==
          1);
  CHECK(err.find(points.string() + ": field 'scan_angle' missing") != std::string::npos);
  REQUIRE(sh(cmd + " --sensor-direction trajectory -o " + (c.dir / "x.json").string(), c.dir / "err", &err) ==
          2);
  REQUIRE(sh(cmd + " --sensor-direction sky -o " + (c.dir / "x.json").string(), c.dir / "err", &err) == 2);
  REQUIRE(sh(cmd + " --trajectory " + traj.string() + " --trajectory-tolerance -1 -o " +
                 (c.dir / "x.json").string(),
             c.dir / "err", &err) == 2);
  const fs::path bad = c.dir / "bad.txt";
  canopy::common::write_file_atomic(bad.string(),
                                    "# canopy trajectory 1\ntime x y z roll pitch heading\n"
                                    "0 -50 0 300 0 0 0\n0 50 0 300 0 0 0\n");
  REQUIRE(sh(cmd + " --trajectory " + bad.string() + " -o " + (c.dir / "x.json").string(), c.dir / "err",
             &err) == 1);
  CHECK(err.find(bad.string() + ": line 4: time 0 is not after") != std::string::npos);
  const fs::path early = c.dir / "early.txt";
  canopy::common::write_file_atomic(early.string(),
                                    "# canopy trajectory 1\ntime x y z roll pitch heading\n"
                                    "0 -50 0 300 0 0 0\n2 50 0 300 0 0 0\n");
  REQUIRE(sh(cmd + " --trajectory " + early.string() + " -o " + (c.dir / "x.json").string(), c.dir / "err",
             &err) == 1);
  CHECK(err.find(early.string() + ": GPS time 5 s is outside the trajectory's span [0, 2]") !=
        std::string::npos);
  CHECK(!fs::exists(c.dir / "x.json"));
}

TEST_CASE("verify --check-trajectory: the file alone, read as --trajectory reads it (stop 71)",
          "[verify][cli]") {
  const fs::path dir = canopy::test::fresh_dir("verify", "checktraj");
  std::string err;
  const fs::path good = dir / "good.traj";
  canopy::common::write_file_atomic(good.string(),
                                    "# canopy trajectory 1\ntime x y z roll pitch heading\n"
                                    "307843211.25 -50 0 300 0 0 0\n307843221.5 50 0 300 0 0 0\n");
  // No --points, no --modelbase, no -i: the trajectory alone, said in one line.
  REQUIRE(sh(kBin + " --check-trajectory " + good.string(), dir / "err", &err) == 0);
  CHECK(err == "verify: " + good.string() +
                   ": a canopy trajectory of 2 samples, time 307843211.25 to 307843221.5 s\n");
  REQUIRE(sh(kBin + " -q --check-trajectory " + good.string(), dir / "err", &err) == 0);
  CHECK(err.empty());
  // Not a trajectory: exit 1, the file, the line and the problem (--trajectory's own words).
  const fs::path notes = dir / "notes.txt";
  canopy::common::write_file_atomic(notes.string(), "time x y z\n1 2 3\n");
  REQUIRE(sh(kBin + " --check-trajectory " + notes.string(), dir / "err", &err) == 1);
  CHECK_THAT(err, Catch::StartsWith("verify: error: " + notes.string() + ": line 1: "));
  const fs::path bad = dir / "bad.traj";
  canopy::common::write_file_atomic(bad.string(),
                                    "# canopy trajectory 1\ntime x y z roll pitch heading\n"
                                    "0 -50 0 300 0 0 0\n0 50 0 300 0 0 0\n");
  REQUIRE(sh(kBin + " --check-trajectory " + bad.string(), dir / "err", &err) == 1);
  CHECK(err.find(bad.string() + ": line 4: time 0 is not after") != std::string::npos);
  REQUIRE(sh(kBin + " --check-trajectory " + (dir / "none.traj").string(), dir / "err", &err) == 1);
  CHECK(err.find((dir / "none.traj").string() + ": cannot open") != std::string::npos);
  // Without the mode (or with it empty) --points and --modelbase are required, as before.
  REQUIRE(sh(kBin + " -i " + good.string(), dir / "err", &err) == 2);
  CHECK(err.find("--points is required") != std::string::npos);
  REQUIRE(sh(kBin + " --check-trajectory '' -i " + good.string(), dir / "err", &err) == 2);
  CHECK(err.find("--points is required") != std::string::npos);
}

TEST_CASE("a match result with poses and no pairs (baseline --hypotheses) is checked without --segments",
          "[verify][cli]") {
  const Case c("hypotheses");
  const Isometry3d T = pose(1.0, 2.0, -1.0);  // where Case put the pickup
  doc::MatchResult h;
  h.provenance = {"baseline", "0", {}, {}};
  h.object = c.points.string();  // baseline records the points it registered to
  h.error_form = "fpfh";
  for (const std::string name : {"pickup", "flatbed"}) {
    doc::ModelScore m;
    m.model = name;
    m.rank = static_cast<int>(h.models.size()) + 1;
    m.score = 0.6 - 0.2 * static_cast<double>(h.models.size());
    h.models.push_back(m);
  }
  std::array<double, 16> a{};
  for (int k = 0; k < 16; ++k) a[static_cast<std::size_t>(k)] = T.matrix()(k / 4, k % 4);
  h.models[0].pose = a;
  const fs::path hyp = c.dir / "hypotheses.json";
  doc::write_match_result(h, hyp.string());
  REQUIRE(canopy::common::read_file(hyp.string()).find("\"pose\"") != std::string::npos);
  const std::string base =
      kBin + " -i " + hyp.string() + " --points " + c.points.string() + " --modelbase " + c.mb.string();
  std::string err;
  REQUIRE(sh(base + " -o " + (c.dir / "v.json").string(), c.dir / "err", &err) == 0);
  const doc::Verdict v = doc::read_verdict((c.dir / "v.json").string());
  REQUIRE(v.model == "pickup");
  REQUIRE(v.chosen == 0);
  CHECK(v.hypotheses[0].start.rfind("pose", 0) == 0);  // the given pose (or its flip) won
  CHECK(v.hypotheses[0].pose.translation[0] == Approx(2.0).margin(1e-3));
  CHECK(v.hypotheses[0].pose.translation[1] == Approx(-1.0).margin(1e-3));
  CHECK(fm::euler_degrees(v.hypotheses[0].pose)[0] == Approx(1.0 * 180 / canopy::common::kPi).margin(0.1));
  // The record names what was read: no segment graph.
  CHECK(v.provenance.inputs == std::vector<std::string>{hyp.string(), c.points.string(), c.mb.string()});
  for (const auto& kv : v.provenance.parameters) CHECK(kv.first != "segments");
  // Its "object" names other points that are there: refused, naming both.
  doc::MatchResult other = h;
  other.object = c.segments.string();
  doc::write_match_result(other, (c.dir / "other.json").string());
  REQUIRE(sh(kBin + " -i " + (c.dir / "other.json").string() + " --points " + c.points.string() +
                 " --modelbase " + c.mb.string() + " -o " + (c.dir / "x.json").string(),
             c.dir / "err", &err) == 1);
  CHECK(err.find("was made from " + c.segments.string() + ", not from " + c.points.string()) !=
        std::string::npos);
  // gmatch's match (pairs) without --segments: a usage error.
  REQUIRE(sh(kBin + " -i " + c.match.string() + " --points " + c.points.string() + " --modelbase " +
                 c.mb.string() + " -o " + (c.dir / "x.json").string(),
             c.dir / "err", &err) == 2);
  CHECK(err.find("--segments is needed") != std::string::npos);
  CHECK(!fs::exists(c.dir / "x.json"));
}

TEST_CASE("gmatch's match results carry no pose: verify checks them as before", "[verify][cli]") {
  // The Case's match is written as gmatch writes one (pairs, no pose): no "pose" key, and the
  // verdict is the pairs/axes one the other tests check.
  const Case c("no-pose");
  const std::string text = canopy::common::read_file(c.match.string());
  CHECK(text.find("pose") == std::string::npos);
  for (const auto& m : doc::read_match_result(c.match.string()).models) CHECK_FALSE(m.pose.has_value());
  std::string err;
  REQUIRE(sh(c.cmd(c.dir / "v.json"), c.dir / "err", &err) == 0);
  const doc::Verdict v = doc::read_verdict((c.dir / "v.json").string());
  for (const auto& h : v.hypotheses) CHECK(h.start.rfind("pose", 0) == std::string::npos);
  CHECK(v.provenance.inputs.size() == 4);  // the segments are read and recorded
}

TEST_CASE("a modelbase surface whose label field is 0 everywhere verifies as one without the field",
          "[verify][cli][surface]") {
  // fitvox writes label 0 on every sample of points without labels (a user's own scan of a
  // vehicle on its ground, a tile candidate): verify takes such a surface's points above 5 cm,
  // as for a surface without the field, and says so in one line. A labelled surface (1 on the
  // vehicle, 3 on the ground) keeps its label-1 rows. All three give the verdict of the Case's
  // plain surfaces (no ground, no labels) byte for byte.
  const Case c("zero-labels");
  std::string err;
  REQUIRE(sh(c.cmd(c.dir / "ref.json"), c.dir / "err", &err) == 0);
  const std::string ref = canopy::common::read_file((c.dir / "ref.json").string());
  const doc::Verdict v = doc::read_verdict((c.dir / "ref.json").string());
  REQUIRE(v.model == "pickup");
  REQUIRE(v.chosen == 1);
  CHECK(fm::euler_degrees(v.hypotheses[1].pose)[0] == Approx(1.0 * 180 / canopy::common::kPi).margin(0.1));
  CHECK(v.hypotheses[1].pose.translation[0] == Approx(2.0).margin(1e-3));
  CHECK(v.hypotheses[1].pose.translation[1] == Approx(-1.0).margin(1e-3));

  const std::vector<std::pair<std::string, std::vector<Box>>> entries{{"pickup", pickup()},
                                                                      {"flatbed", flatbed()}};
  auto write_surfaces = [&](const std::string& kind) {
    for (const auto& [name, boxes] : entries) {
      const canopy::verify::Surface car = sample(boxes, 0.1), scan = on_ground(car, boxes);
      std::vector<std::uint32_t> labels(scan.points.size(), kind == "labelled" ? 3 : 0);
      if (kind == "labelled") std::fill_n(labels.begin(), car.points.size(), 1u);
      fm::write_pcd(surface_pcd(scan, kind == "no field" ? nullptr : &labels),
                    (c.mb / (name + ".pcd")).string());
    }
  };
  const std::string note = "with a label field of 0 (unknown) only";
  for (const std::string kind : {"no field", "zeros", "labelled"}) {
    INFO(kind);
    write_surfaces(kind);
    const fs::path out = c.dir / (kind == "no field" ? "none.json" : kind + ".json");
    REQUIRE(sh(c.cmd(out), c.dir / "err", &err) == 0);
    CHECK(canopy::common::read_file(out.string()) == ref);
    const auto at = err.find(note);
    if (kind == "zeros") {
      // One line naming both surfaces.
      REQUIRE(at != std::string::npos);
      CHECK(err.find(note, at + 1) == std::string::npos);
      const std::string line =
          err.substr(err.rfind('\n', at) + 1, err.find('\n', at) - err.rfind('\n', at) - 1);
      CHECK(line.rfind("verify: 2 modelbase surfaces with a label field of 0", 0) == 0);
      CHECK(line.find((c.mb / "pickup.pcd").string()) != std::string::npos);
      CHECK(line.find((c.mb / "flatbed.pcd").string()) != std::string::npos);
      // -q keeps it quiet, as verify's other information.
      REQUIRE(sh(c.cmd(c.dir / "q.json") + " -q", c.dir / "err", &err) == 0);
      CHECK(err.empty());
    } else {
      CHECK(at == std::string::npos);
    }
  }

  // Labels 0 everywhere and nothing above the ground: an error naming the surface, no output.
  const canopy::verify::Surface flat = on_ground(canopy::verify::Surface{}, pickup());
  const std::vector<std::uint32_t> zeros(flat.points.size(), 0);
  fm::write_pcd(surface_pcd(flat, &zeros), (c.mb / "pickup.pcd").string());
  REQUIRE(sh(c.cmd(c.dir / "flat.json"), c.dir / "err", &err) == 1);
  CHECK(err.find((c.mb / "pickup.pcd").string() + ": no model surface points") != std::string::npos);
  CHECK(err.find("0 (unknown) everywhere") != std::string::npos);
  CHECK(!fs::exists(c.dir / "flat.json"));
  // Labelled without label 1 (only ground, 3): an error as before, naming the labels.
  const std::vector<std::uint32_t> threes(flat.points.size(), 3);
  fm::write_pcd(surface_pcd(flat, &threes), (c.mb / "pickup.pcd").string());
  REQUIRE(sh(c.cmd(c.dir / "g.json"), c.dir / "err", &err) == 1);
  CHECK(err.find((c.mb / "pickup.pcd").string() + ": no model surface points") != std::string::npos);
  CHECK(err.find("label 1; it holds 3)") != std::string::npos);
  CHECK(!fs::exists(c.dir / "g.json"));
}

TEST_CASE("verify: without a runner-up the margin over the next model is no evidence (review F10)",
          "[verify][cli]") {
  // The pickup first in the match, the flatbed second: with -k 2 the flatbed is scored as the
  // runner-up; with -k 1 (as with a one-entry modelbase) no other model is. The answer is the
  // pickup both times; alone it may not be surer than beside a scored runner-up (before stop 71
  // the whole score counted as its lead over nothing, and -k 1 stated the higher confidence).
  Case c("no-runner-up");
  doc::write_match_result(Case::match_of({"pickup", "flatbed"}), c.match.string());
  std::string err;
  REQUIRE(sh(c.cmd(c.dir / "k2.json") + " -k 2", c.dir / "err", &err) == 0);
  REQUIRE(sh(c.cmd(c.dir / "k1.json") + " -k 1", c.dir / "err", &err) == 0);
  const canopy::documents::Verdict two = canopy::documents::read_verdict((c.dir / "k2.json").string());
  const canopy::documents::Verdict one = canopy::documents::read_verdict((c.dir / "k1.json").string());
  REQUIRE(two.hypotheses.size() == 2);
  REQUIRE(one.hypotheses.size() == 1);
  CHECK(two.model == "pickup");
  CHECK(one.model == "pickup");
  REQUIRE(two.hypotheses[1].score > 0);
  CHECK(one.hypotheses[0].score == Approx(two.hypotheses[0].score));
  CHECK(one.confidence < two.confidence);
}
