// The PCL baseline on analytic cases: a posed, partly occluded box is recognised as the box
// (not the cylinder) by both methods, and the local method recovers its pose.
#include <catch2/catch.hpp>

#include <cmath>

#include "baseline/baseline.h"
#include "canopy/common/error.h"
#include "shapes.h"

namespace bl = canopy::baseline;
using namespace baseline_test;

namespace {

std::vector<bl::Model> box_and_cylinder() { return {{"box", box()}, {"cylinder", cylinder()}}; }

// Heading of a pose's rotation about z, and its tilt (angle of the rotated z axis from z).
double heading_of(const Eigen::Matrix4d& m) { return std::atan2(m(1, 0), m(0, 0)); }
double tilt_of(const Eigen::Matrix4d& m) { return std::acos(std::clamp(m(2, 2), -1.0, 1.0)); }

// Heading difference modulo the box's 180-degree symmetry, in [0, pi/2].
double heading_error_mod_pi(double a, double b) {
  double d = std::fmod(std::fabs(a - b), M_PI);
  return std::min(d, M_PI - d);
}

}  // namespace

TEST_CASE("baseline: an occluded box ranks the box first in both methods, pose recovered", "[baseline]") {
  const double heading = 0.6;
  const Eigen::Vector3d t(3.0, -2.0, 0.0);
  const Cloud raw = scene(box(), pose(heading, t), {-std::sin(heading), std::cos(heading), 0}, 0.01, 7);
  const Cloud cand = bl::candidate_from_cloud(to_cloud(raw), "scene", 0.3);
  REQUIRE(cand.points.size() < raw.points.size());  // the ground went below the cut
  for (const auto& p : cand.points) REQUIRE(p.z() >= 0.3f);

  bl::Params p;
  const std::vector<bl::Model> models = box_and_cylinder();
  const bl::Result r = bl::run(p, {&cand, &models});
  REQUIRE(r.methods.size() == 2);
  for (const auto& m : r.methods) {
    INFO(m.method);
    REQUIRE(m.models.size() == 2);
    CHECK(m.models[0].model == "box");
    CHECK(m.models[0].rank == 1);
    CHECK(m.models[0].score > m.models[1].score);
  }
  const bl::Entry& best = r.methods[1].models[0];
  REQUIRE(r.methods[1].method == "fpfh");
  REQUIRE(best.posed);
  CHECK(best.fitness > 0.8);
  CHECK(heading_error_mod_pi(heading_of(best.pose), heading) < 5.0 * M_PI / 180);
  CHECK(tilt_of(best.pose) < 5.0 * M_PI / 180);
  // The box's centre (0, 0, 0.9) maps to the scene's.
  const Eigen::Vector3d c = (best.pose * Eigen::Vector4d(0, 0, 0.9, 1)).head<3>();
  CHECK((c - (t + Eigen::Vector3d(0, 0, 0.9))).norm() < 0.15);
}

TEST_CASE("baseline: an occluded cylinder ranks the cylinder first", "[baseline]") {
  const double heading = -1.1;
  const Cloud raw = scene(cylinder(), pose(heading, {-5, 1, 0}), {0, 0, -1}, 0.01, 8);
  const Cloud cand = bl::candidate_from_cloud(to_cloud(raw), "scene", 0.3);
  const std::vector<bl::Model> models = box_and_cylinder();
  const bl::Result r = bl::run(bl::Params{}, {&cand, &models});
  for (const auto& m : r.methods) {
    INFO(m.method);
    CHECK(m.models[0].model == "cylinder");
  }
  const bl::Entry& best = r.methods[1].models[0];
  REQUIRE(best.posed);
  // The axis direction (x in the model) maps to the scene's axis, either way round.
  const Eigen::Vector3d axis = best.pose.block<3, 3>(0, 0) * Eigen::Vector3d::UnitX();
  CHECK(std::fabs(axis.dot(Eigen::Vector3d(std::cos(heading), std::sin(heading), 0))) > 0.99);
}

TEST_CASE("baseline: same inputs and seed, same bytes", "[baseline]") {
  const Cloud raw = scene(box(), pose(2.0, {1, 1, 0}), {1, 0, 0}, 0.02, 9);
  const Cloud cand = bl::candidate_from_cloud(to_cloud(raw), "scene", 0.3);
  const auto models = box_and_cylinder();
  const std::string a = bl::serialize(bl::run(bl::Params{}, {&cand, &models}), "s", {}, {"s"});
  const std::string b = bl::serialize(bl::run(bl::Params{}, {&cand, &models}), "s", {}, {"s"});
  CHECK(a == b);
  CHECK(a.find("\"format\": \"canopy.baseline\"") != std::string::npos);
}

TEST_CASE("baseline: a model surface's label field of 0 everywhere carries no labels", "[baseline]") {
  // Two points below the 5 cm ground cut, three above: labelled (1 on the lower two only) the
  // model is its label-1 rows; with 0 on every row (fitvox's for unlabelled input) or without
  // the field, the rows above the cut (stop 70; before, 0 everywhere kept nothing and threw).
  Cloud raw;
  raw.points = {{0, 0, 0.0f}, {1, 0, 0.02f}, {0, 0, 1.0f}, {1, 0, 1.0f}, {0, 1, 1.0f}};
  raw.normals.assign(5, Eigen::Vector3f(0, 0, 1));
  auto pc = to_cloud(raw);
  const Cloud plain = bl::model_from_cloud(pc, "m");
  CHECK(plain.points.size() == 3);
  pc.add("label", canopy::formats::kUint32) = {0, 0, 0, 0, 0};
  const Cloud zero = bl::model_from_cloud(pc, "m");
  REQUIRE(zero.points.size() == 3);
  for (std::size_t i = 0; i < 3; ++i) CHECK(zero.points[i] == plain.points[i]);
  pc.col("label") = {3, 3, 1, 1, 1};
  CHECK(bl::model_from_cloud(pc, "m").points.size() == 3);
  pc.col("label") = {3, 3, 2, 2, 2};
  CHECK_THROWS_AS(bl::model_from_cloud(pc, "m"), canopy::common::DataError);
}

TEST_CASE("baseline: bad inputs and parameters are rejected", "[baseline]") {
  canopy::formats::PointCloud empty;
  CHECK_THROWS_AS(bl::candidate_from_cloud(empty, "e", 0.3), canopy::common::DataError);
  // Everything below the ground cut: no candidate.
  Cloud flat;
  flat.points = {{0, 0, 0.1f}, {1, 0, 0.1f}, {0, 1, 0.1f}};
  flat.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  CHECK_THROWS_AS(bl::candidate_from_cloud(to_cloud(flat), "f", 0.3), canopy::common::DataError);
  // Normals are required.
  auto pc = to_cloud(box());
  pc.remove("normal_z");
  CHECK_THROWS_AS(bl::model_from_cloud(pc, "m"), canopy::common::DataError);
  bl::Params p;
  p.feature_radius = p.normal_radius;
  CHECK_THROWS_AS(bl::validate(p), canopy::common::UsageError);
  p = bl::Params{};
  p.ransac_iterations = 0;
  CHECK_THROWS_AS(bl::validate(p), canopy::common::UsageError);
}
