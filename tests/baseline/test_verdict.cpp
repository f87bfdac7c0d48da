// The baseline's answer per candidate (baseline --verdict METHOD, a canopy.verdict read by
// collect): the acceptance rule on hand-built rankings, the right model and pose of an occluded
// analytic box, none for a shape that is not in the modelbase, and the binary's output; the
// ranking with its poses as a match result for verify (--hypotheses).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "baseline/baseline.h"
#include "canopy/common/atomic_file.h"
#include "canopy/documents/match_result.h"
#include "canopy/formats/pcd.h"
#include "canopy/documents/verdict.h"
#include "shapes.h"
#include "support/cli.h"

namespace bl = canopy::baseline;
namespace fs = std::filesystem;
using namespace baseline_test;

namespace {

const canopy::formats::Provenance kProv{"baseline", "test", {}, {"s.pcd"}};

bl::Entry entry(const std::string& model, int rank, double score, bool posed) {
  bl::Entry e;
  e.model = model;
  e.rank = rank;
  e.score = score;
  e.fitness = score;
  e.candidate_share = score;
  e.posed = posed;
  if (posed) {
    e.pose = Eigen::Matrix4d::Identity();
    e.pose.block<3, 3>(0, 0) = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    e.pose(0, 3) = 2;
    e.pose(1, 3) = -1;
  }
  return e;
}

double heading_deg(const canopy::formats::Pose& p) { return canopy::formats::euler_degrees(p)[0]; }

// A crate of 1 x 1 x 1 m on the ground: an object of the tiles' clutter, not a vehicle.
Cloud crate() { return box(1.0, 1.0, 1.0, 0.0, 0.1); }

}  // namespace

TEST_CASE("baseline verdict: the best model at or above the threshold, else none", "[baseline]") {
  bl::Ranking r;
  r.method = "fpfh";
  r.models = {entry("box", 1, 0.6, true), entry("cylinder", 2, 0.2, true)};

  const auto yes = bl::to_verdict(r, 0.6, "s.pcd", kProv);
  CHECK(yes.model == "box");
  CHECK(yes.chosen == 0);
  CHECK(yes.confidence == Approx(0.6));
  REQUIRE(yes.hypotheses.size() == 2);
  CHECK(yes.hypotheses[1].model == "cylinder");
  CHECK(yes.hypotheses[1].gmatch_rank == 2);
  CHECK(yes.hypotheses[0].start == "fpfh");
  CHECK(yes.hypotheses[0].explained == Approx(0.6));
  CHECK(heading_deg(yes.hypotheses[0].pose) == Approx(0.5 * 180 / M_PI));
  CHECK(yes.hypotheses[0].pose.translation[0] == Approx(2));
  CHECK(yes.hypotheses[0].pose.translation[1] == Approx(-1));

  const auto no = bl::to_verdict(r, 0.61, "s.pcd", kProv);
  CHECK(no.model.empty());
  CHECK(no.chosen == -1);
  CHECK(no.confidence == Approx(0.4));
  CHECK(no.hypotheses.size() == 2);  // the ranking is kept
  // The file: model null, pose null, read back by the verdict reader.
  const auto back = canopy::documents::parse_verdict(canopy::documents::serialize_verdict(no), "v");
  CHECK(back.model.empty());
  CHECK(back.chosen == -1);

  // RANSAC found no pose for any model: never an answer, whatever the threshold.
  r.models = {entry("box", 1, 0.0, false), entry("cylinder", 2, 0.0, false)};
  const auto unposed = bl::to_verdict(r, 0.0, "s.pcd", kProv);
  CHECK(unposed.model.empty());
  CHECK(unposed.confidence == Approx(1.0));

  // VFH has no pose: its answer stands at the candidate frame's origin (identity).
  bl::Ranking v;
  v.method = "vfh";
  v.models = {entry("cylinder", 1, 0.9, false), entry("box", 2, 0.8, false)};
  const auto g = bl::to_verdict(v, 0.85, "s.pcd", kProv);
  CHECK(g.model == "cylinder");
  CHECK(g.hypotheses[0].pose.rotation == canopy::formats::Pose{}.rotation);
  CHECK(g.hypotheses[0].pose.translation == canopy::formats::Pose{}.translation);
  CHECK(bl::to_verdict(v, 0.95, "s.pcd", kProv).model.empty());
}

TEST_CASE("baseline verdict: an occluded box is the box, posed; a crate is none", "[baseline]") {
  bl::Params p;  // the shipped thresholds (share/params/baseline.ini has the same)
  p.methods = "fpfh";
  REQUIRE(p.accept_fpfh > 0);
  const std::vector<bl::Model> models = {{"box", box()}, {"cylinder", cylinder()}};

  const double heading = 0.6;
  const Eigen::Vector3d t(3.0, -2.0, 0.0);
  const Cloud cand = bl::candidate_from_cloud(
      to_cloud(scene(box(), pose(heading, t), {-std::sin(heading), std::cos(heading), 0}, 0.01, 7)), "box",
      0.3);
  const auto r = bl::run(p, {&cand, &models});
  const auto v = bl::to_verdict(r.methods.at(0), p.accept_fpfh, "box.pcd", kProv);
  REQUIRE(v.model == "box");
  CHECK(v.confidence >= p.accept_fpfh);
  const auto& pose_v = v.hypotheses.at(v.chosen).pose;
  // Heading modulo the box's 180-degree symmetry within 5 degrees; the box's centre within 15 cm.
  double d = std::fmod(std::fabs(heading_deg(pose_v) - heading * 180 / M_PI), 180.0);
  CHECK(std::min(d, 180 - d) < 5);
  const Eigen::Vector3d c(pose_v.translation[0], pose_v.translation[1], pose_v.translation[2]);
  CHECK((c.head<2>() - t.head<2>()).norm() < 0.15);

  // The crate, posed and with one side hidden like the box: its best fit explains the crate but
  // covers little of either model, so its fitness is below the threshold.
  const Cloud crate_cand = bl::candidate_from_cloud(
      to_cloud(scene(crate(), pose(0.3, {-2, 4, 0}), {0, 1, 0}, 0.01, 11)), "crate", 0.3);
  const auto rc = bl::run(p, {&crate_cand, &models});
  INFO("crate: best " << rc.methods[0].models[0].model << " fitness " << rc.methods[0].models[0].score);
  CHECK(rc.methods[0].models[0].score < p.accept_fpfh);
  const auto vc = bl::to_verdict(rc.methods[0], p.accept_fpfh, "crate.pcd", kProv);
  CHECK(vc.model.empty());
  CHECK(vc.chosen == -1);
}

TEST_CASE("baseline --verdict writes a canopy.verdict", "[baseline][cli]") {
  const fs::path dir = canopy::test::fresh_dir("baseline", "verdict");
  fs::create_directories(dir / "modelbase");
  canopy::formats::write_pcd(to_cloud(box()), (dir / "modelbase" / "box.pcd").string());
  canopy::formats::write_pcd(to_cloud(cylinder()), (dir / "modelbase" / "cylinder.pcd").string());
  canopy::formats::write_pcd(to_cloud(scene(box(), pose(1.0, {2, 3, 0}), {0, 1, 0}, 0.01, 3)),
                             (dir / "samples.pcd").string());
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/baseline";
  const std::string base =
      bin + " -i " + (dir / "samples.pcd").string() + " --modelbase " + (dir / "modelbase").string();
  std::string err;
  REQUIRE(canopy::test::sh(base + " --verdict fpfh -o " + (dir / "f.json").string(), dir / "err", &err) == 0);
  const auto f = canopy::documents::read_verdict((dir / "f.json").string());
  CHECK(f.model == "box");
  CHECK(f.provenance.tool == "baseline");
  CHECK(f.hypotheses.size() == 2);
  const auto j = nlohmann::json::parse(canopy::common::read_file((dir / "f.json").string()));
  CHECK(j["format"] == "canopy.verdict");
  CHECK(j["pose"]["matrix"].size() == 16);
  // A threshold above any fitness: none.
  REQUIRE(canopy::test::sh(base + " --verdict fpfh --accept-fpfh 1 -o " + (dir / "n.json").string(),
                           dir / "err", &err) == 0);
  CHECK(canopy::documents::read_verdict((dir / "n.json").string()).model.empty());
  // The verdict's method against another one named: a usage error, no output.
  CHECK(canopy::test::sh(base + " --verdict fpfh --methods vfh -o " + (dir / "u.json").string(), dir / "err",
                         &err) == 2);
  CHECK_FALSE(fs::exists(dir / "u.json"));
  CHECK(canopy::test::sh(base + " --verdict esf -o " + (dir / "u.json").string(), dir / "err", &err) == 2);
  CHECK(canopy::test::sh(base + " --verdict vfh --accept-vfh 1.5 -o " + (dir / "u.json").string(),
                         dir / "err", &err) == 2);
  CHECK_FALSE(fs::exists(dir / "u.json"));
}

TEST_CASE("baseline hypotheses: the ranking as a match result, a pose only where RANSAC found one",
          "[baseline]") {
  bl::Ranking r;
  r.method = "fpfh";
  r.models = {entry("box", 1, 0.6, true), entry("cylinder", 2, 0.2, true), entry("crate", 3, 0.0, false)};
  const canopy::documents::MatchResult m = bl::to_match_result(r, "s.pcd", kProv);
  CHECK(m.object == "s.pcd");
  CHECK(m.error_form == "fpfh");
  CHECK(m.provenance.tool == "baseline");
  REQUIRE(m.models.size() == 3);
  for (std::size_t k = 0; k < 3; ++k) {
    INFO(k);
    CHECK(m.models[k].model == r.models[k].model);
    CHECK(m.models[k].rank == static_cast<int>(k) + 1);
    CHECK(m.models[k].score == r.models[k].score);
    CHECK(m.models[k].error_total == 0);
    CHECK(m.models[k].pairs.empty());
  }
  // The pose row-major as the entry holds it (model -> candidate): heading 0.5 rad, (2, -1, 0).
  REQUIRE(m.models[0].pose.has_value());
  const auto& a = *m.models[0].pose;
  for (int k = 0; k < 16; ++k) CHECK(a[static_cast<std::size_t>(k)] == r.models[0].pose(k / 4, k % 4));
  CHECK(std::atan2(a[4], a[0]) == Approx(0.5));
  CHECK(a[3] == 2);
  CHECK(a[7] == -1);
  CHECK(m.models[1].pose.has_value());
  CHECK_FALSE(m.models[2].pose.has_value());  // RANSAC did not converge: no pose
  // Entropy over the scores 0.6, 0.2, 0 (normalised 0.75, 0.25): 0.811 bits.
  CHECK(m.entropy == Approx(-(0.75 * std::log2(0.75) + 0.25 * std::log2(0.25))));
  // The file: the unposed model has no "pose" key; margin = 0.6 - 0.2.
  const std::string text = canopy::documents::serialize_match_result(m);
  const auto j = nlohmann::json::parse(text);
  CHECK(j["models"][0]["pose"].size() == 16);
  CHECK_FALSE(j["models"][2].contains("pose"));
  CHECK(j["margin"].get<double>() == Approx(0.4));
}

TEST_CASE(
    "baseline --verdict fpfh --hypotheses: every model ranked, rank 1 the verdict's, posed near the truth",
    "[baseline][cli]") {
  const fs::path dir = canopy::test::fresh_dir("baseline", "hypotheses");
  fs::create_directories(dir / "modelbase");
  canopy::formats::write_pcd(to_cloud(box()), (dir / "modelbase" / "box.pcd").string());
  canopy::formats::write_pcd(to_cloud(cylinder()), (dir / "modelbase" / "cylinder.pcd").string());
  const double heading = 1.0;
  const Eigen::Vector3d t(2, 3, 0);
  canopy::formats::write_pcd(to_cloud(scene(box(), pose(heading, t), {0, 1, 0}, 0.01, 3)),
                             (dir / "samples.pcd").string());
  const std::string bin = std::string(CANOPY_BIN_DIR) + "/baseline";
  const std::string base =
      bin + " -i " + (dir / "samples.pcd").string() + " --modelbase " + (dir / "modelbase").string();
  std::string err;
  REQUIRE(canopy::test::sh(base + " --verdict fpfh -o " + (dir / "plain.json").string(), dir / "err", &err) ==
          0);
  REQUIRE(canopy::test::sh(base + " --verdict fpfh -o " + (dir / "v.json").string() + " --hypotheses " +
                               (dir / "h.json").string(),
                           dir / "err", &err) == 0);
  // The verdict is the one written without --hypotheses, byte for byte.
  CHECK(canopy::common::read_file((dir / "v.json").string()) ==
        canopy::common::read_file((dir / "plain.json").string()));
  const auto v = canopy::documents::read_verdict((dir / "v.json").string());
  REQUIRE(v.model == "box");
  const auto h = canopy::documents::read_match_result((dir / "h.json").string());
  CHECK(h.provenance.tool == "baseline");
  CHECK(h.object == (dir / "samples.pcd").string());
  REQUIRE(h.models.size() == 2);  // every model of the modelbase
  CHECK(h.models[0].model == v.model);
  CHECK(h.models[0].rank == 1);
  CHECK(h.models[1].model == "cylinder");
  CHECK(h.models[0].score == v.hypotheses[0].score);
  CHECK(h.models[0].score > h.models[1].score);
  REQUIRE(h.models[0].pose.has_value());
  const auto& a = *h.models[0].pose;
  // The verdict's pose, the same numbers; and near the truth: heading modulo the box's
  // 180-degree symmetry within 5 degrees, the centre within 15 cm.
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) CHECK(a[4 * r + c] == v.hypotheses[0].pose.rotation[3 * r + c]);
    CHECK(a[4 * r + 3] == v.hypotheses[0].pose.translation[r]);
  }
  double d = std::fmod(std::fabs(std::atan2(a[4], a[0]) - heading) * 180 / M_PI, 180.0);
  CHECK(std::min(d, 180 - d) < 5);
  CHECK(std::hypot(a[3] - t.x(), a[7] - t.y()) < 0.15);
  // Same seed, same bytes.
  REQUIRE(canopy::test::sh(base + " --verdict fpfh -o " + (dir / "v2.json").string() + " --hypotheses " +
                               (dir / "h2.json").string(),
                           dir / "err", &err) == 0);
  CHECK(canopy::common::read_file((dir / "h.json").string()) ==
        canopy::common::read_file((dir / "h2.json").string()));
  // Only with --verdict fpfh: a usage error otherwise, and no output at all.
  for (const std::string& other : {std::string(""), std::string(" --verdict vfh"), std::string(" --prepare")}) {
    INFO(other);
    CHECK(canopy::test::sh(base + other + " -o " + (dir / "u.json").string() + " --hypotheses " +
                               (dir / "uh.json").string(),
                           dir / "err", &err) == 2);
    CHECK(err.find("--hypotheses needs --verdict fpfh") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "u.json"));
    CHECK_FALSE(fs::exists(dir / "uh.json"));
  }
  // The verdict and the hypotheses in one file: a usage error before any work.
  CHECK(canopy::test::sh(base + " --verdict fpfh -o " + (dir / "u.json").string() + " --hypotheses " +
                             (dir / "." / "u.json").string(),
                         dir / "err", &err) == 2);
  CHECK_FALSE(fs::exists(dir / "u.json"));
}
