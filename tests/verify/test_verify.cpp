// verify's logic on synthetic vehicles with known poses: recovery to 1 mm / 0.1 degree, the
// 180-degree flip rejected, another model's points scoring below their own model, clutter
// answered none; a match result's own pose (baseline --hypotheses) as the start.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>

#include "canopy/common/math.h"
#include "canopy/common/error.h"
#include "canopy/formats/pose_eigen.h"
#include "fixtures.h"
#include "verify/verify.h"

using namespace verify_test;
namespace vf = canopy::verify;
namespace doc = canopy::documents;
namespace fm = canopy::formats;

namespace {

double angle_deg(const Isometry3d& a, const Isometry3d& b) {
  const Eigen::AngleAxisd d(a.linear().transpose() * b.linear());
  return std::abs(d.angle()) * 180 / canopy::common::kPi;
}

struct World {
  std::vector<vf::Model> models;
  World() {
    models.push_back({"pickup", graph(pickup()), sample(pickup(), 0.1), ""});
    models.push_back({"flatbed", graph(flatbed()), sample(flatbed(), 0.1), ""});
  }
};

}  // namespace

TEST_CASE("a posed, resampled model is recovered to 1 mm and 0.1 degree", "[verify]") {
  const World w;
  const Isometry3d T = pose(0.7, 1.2, -0.4);
  // The candidate is sampled on a grid shifted by half a spacing: no point equals a model point.
  const auto cand = candidate(sample(pickup(), 0.1, 0.05), pickup(), T);
  const auto object = posed(graph(pickup()), T);
  const auto m = match({"pickup", "flatbed"}, {graph(pickup()), graph(flatbed())}, true);
  const canopy::documents::Verdict v = vf::run(vf::Params{}, {&cand, &object, &m, &w.models});
  REQUIRE(v.model == "pickup");
  REQUIRE(v.chosen == 0);
  const auto& h = v.hypotheses[0];
  const Isometry3d P = fm::to_isometry(h.pose);
  CHECK((P.translation() - T.translation()).norm() < 1e-3);
  CHECK(angle_deg(P, T) < 0.1);
  CHECK(h.explained > 0.9);
  CHECK(h.free_space_violation < 0.05);
  CHECK(h.fit_rms < 1e-3);
  CHECK(v.confidence > 0.9);
  CHECK(v.confidence <= 1.0);
  // The other hypothesis is checked and scores lower.
  REQUIRE(v.hypotheses.size() == 2);
  CHECK(v.hypotheses[1].score < h.score - 0.3);
}

TEST_CASE("recovery does not need the segment pairs (principal-axis start)", "[verify]") {
  const World w;
  const Isometry3d T = pose(-2.0, -0.3, 0.5);
  const auto cand = candidate(sample(pickup(), 0.1, 0.05), pickup(), T);
  const auto object = posed(graph(pickup()), T);
  const auto m = match({"pickup"}, {graph(pickup())}, false);
  const canopy::documents::Verdict v = vf::run(vf::Params{}, {&cand, &object, &m, &w.models});
  REQUIRE(v.model == "pickup");
  const Isometry3d P = fm::to_isometry(v.hypotheses[0].pose);
  CHECK((P.translation() - T.translation()).norm() < 1e-3);
  CHECK(angle_deg(P, T) < 0.1);
  CHECK(v.hypotheses[0].start.rfind("axes", 0) == 0);
}

TEST_CASE("the 180-degree flipped pose is rejected", "[verify]") {
  const World w;
  const Isometry3d T = pose(0.3, 0.2, 0.1);
  const auto cand = candidate(sample(pickup(), 0.1, 0.05), pickup(), T);
  const vf::Params p;
  const vf::Scorer scorer(cand, p);
  const auto& model = w.models[0].surface;
  const Isometry3d F = pose(0.3 + canopy::common::kPi, 0.2, 0.1);  // same place, turned round
  const vf::Check right = scorer.score(model, vf::refine(model, scorer.above_points(), T, p));
  const vf::Check flip = scorer.score(model, vf::refine(model, scorer.above_points(), F, p));
  CHECK(right.score > 0.9);
  CHECK(flip.score < right.score - 0.2);
  CHECK(flip.violation > right.violation);
  // run() tries the flip of the pairs' start explicitly and keeps the right one.
  const auto object = posed(graph(pickup()), T);
  const auto m = match({"pickup"}, {graph(pickup())}, true);
  const canopy::documents::Verdict v = vf::run(p, {&cand, &object, &m, &w.models});
  REQUIRE(v.chosen == 0);
  CHECK(!v.hypotheses[0].flipped);
  CHECK(v.hypotheses[0].flip_score < v.hypotheses[0].score - 0.2);
  CHECK(angle_deg(fm::to_isometry(v.hypotheses[0].pose), T) < 0.1);
}

TEST_CASE("a candidate made of another model's points scores below its own model", "[verify]") {
  const World w;
  const Isometry3d T = pose(2.2, 0.4, -0.2);
  const auto cand = candidate(sample(flatbed(), 0.1, 0.05), flatbed(), T);
  const auto object = posed(graph(flatbed()), T);
  // gmatch (wrongly) ranked the pickup first.
  auto m = match({"pickup", "flatbed"}, {graph(pickup()), graph(flatbed())}, false);
  const canopy::documents::Verdict v = vf::run(vf::Params{}, {&cand, &object, &m, &w.models});
  REQUIRE(v.hypotheses.size() == 2);
  CHECK(v.hypotheses[0].model == "pickup");
  CHECK(v.hypotheses[0].score < v.hypotheses[1].score - 0.3);
  CHECK(v.model == "flatbed");
  // And the pickup's own points score the pickup above the flatbed.
  const auto cand2 = candidate(sample(pickup(), 0.1, 0.05), pickup(), T);
  const vf::Params p;
  const vf::Scorer scorer(cand2, p);
  const auto own = scorer.score(w.models[0].surface, T);
  const auto other =
      scorer.score(w.models[1].surface, vf::refine(w.models[1].surface, scorer.above_points(), T, p));
  CHECK(other.score < own.score - 0.3);
}

TEST_CASE("a box and a sphere are answered none", "[verify]") {
  const World w;
  const auto m = match({"pickup", "flatbed"}, {graph(pickup()), graph(flatbed())}, false);
  const doc::SegmentGraph object;  // no pairs needed: all NULL
  SECTION("the 1.6 x 1.2 x 0.9 m rock") {
    const std::vector<Box> rock{{{-0.8, -0.6, 0.0}, {0.8, 0.6, 0.9}}};
    const auto cand = candidate(sample(rock, 0.1, 0.05), rock, pose(0.4, 0.3, 0.2));
    const canopy::documents::Verdict v = vf::run(vf::Params{}, {&cand, &object, &m, &w.models});
    CHECK(v.model.empty());
    CHECK(v.chosen == -1);
    CHECK(v.confidence > 0.5);
    for (const auto& h : v.hypotheses) CHECK(h.score < vf::Params{}.accept);
  }
  SECTION("a sphere of radius 1 m") {
    const std::vector<Box> footprint{{{-1, -1, 0}, {1, 1, 2}}};
    const auto cand = candidate(sphere(1.0, 0.6, 0.1), footprint, pose(0, 0, 0));
    const canopy::documents::Verdict v = vf::run(vf::Params{}, {&cand, &object, &m, &w.models});
    CHECK(v.model.empty());
    CHECK(v.chosen == -1);
  }
}

TEST_CASE("candidate input checks name the file", "[verify]") {
  fm::PointCloud empty;
  CHECK_THROWS_WITH(vf::candidate_from_cloud(empty, "c.pcd"),
                    Catch::Contains("c.pcd") && Catch::Contains("empty"));
  const auto cand = candidate(sample(pickup(), 0.2), pickup(), pose(0, 0, 0));
  CHECK_THROWS_WITH(vf::candidate_from_cloud(to_cloud(cand, false), "n.pcd"),
                    Catch::Contains("n.pcd") && Catch::Contains("normal_x"));
  CHECK(vf::candidate_from_cloud(to_cloud(cand), "ok.pcd").points.size() == cand.points.size());
  vf::Params p;
  p.top_k = 0;
  CHECK_THROWS_AS(vf::validate(p), canopy::common::UsageError);
}

TEST_CASE("a modelbase surface: label-1 rows if labelled, else (no field, or 0 everywhere) above the ground",
          "[verify][surface]") {
  const vf::Surface car = sample(pickup(), 0.1);  // z >= 0.3 everywhere
  const vf::Surface scan = on_ground(car, pickup());
  const std::size_t n = scan.points.size(), nv = car.points.size();
  REQUIRE(n > nv + 100);
  auto same = [](const vf::Surface& a, const vf::Surface& b) {
    return a.points == b.points && a.normals == b.normals;
  };
  bool zero = true;
  SECTION("no label field: the points above 5 cm, as before") {
    const vf::Surface s = vf::surface_from_cloud(surface_pcd(scan), "plain.pcd", vf::kSurfaceMinZ, &zero);
    CHECK(same(s, car));
    CHECK(!zero);
  }
  SECTION("a label field of 0 everywhere (fitvox on unlabelled points): the same rows, and said so") {
    const std::vector<std::uint32_t> zeros(n, 0);
    const vf::Surface s =
        vf::surface_from_cloud(surface_pcd(scan, &zeros), "zero.pcd", vf::kSurfaceMinZ, &zero);
    CHECK(same(s, car));
    CHECK(zero);
    // The default cut is 5 cm: the z = 0.04 ground rows stay out, a lower cut takes them.
    CHECK(vf::surface_from_cloud(surface_pcd(scan, &zeros), "zero.pcd", 0.03).points.size() > nv + 50);
  }
  SECTION("labelled (1 and 0/2/3): exactly the label-1 rows, whatever their height") {
    std::vector<std::uint32_t> labels(n, 3);  // the ground
    for (std::size_t i = 0; i < nv; ++i) labels[i] = 1;
    labels[0] = 0;       // a vehicle sample of unknown label: left out although above the ground
    labels[1] = 2;       // one labelled foliage: left out
    labels[nv + 4] = 1;  // a ground sample labelled vehicle: kept although at z = 0
    const vf::Surface s =
        vf::surface_from_cloud(surface_pcd(scan, &labels), "lab.pcd", vf::kSurfaceMinZ, &zero);
    CHECK(!zero);
    REQUIRE(s.points.size() == nv - 1);
    CHECK(s.points.front() == car.points[2]);
    CHECK(s.points.back() == scan.points[nv + 4]);
    CHECK(s.points.back().z() == 0.0);
    // Labels 1 on the vehicle, 0 elsewhere: the vehicle's rows, as without labels here.
    std::vector<std::uint32_t> ones(n, 0);
    for (std::size_t i = 0; i < nv; ++i) ones[i] = 1;
    CHECK(same(vf::surface_from_cloud(surface_pcd(scan, &ones), "ones.pcd"), car));
  }
  SECTION("labelled without label 1: an error naming the file and the labels it holds") {
    std::vector<std::uint32_t> labels(n, 0);
    for (std::size_t i = nv; i < n; ++i) labels[i] = 3;
    CHECK_THROWS_WITH(vf::surface_from_cloud(surface_pcd(scan, &labels), "g.pcd"),
                      Catch::Contains("g.pcd") && Catch::Contains("no model surface points") &&
                          Catch::Contains("label 1; it holds 0, 3"));
  }
  SECTION("without labels and nothing above the ground: an error naming the file") {
    const vf::Surface ground = on_ground(vf::Surface{}, pickup());
    const std::vector<std::uint32_t> zeros(ground.points.size(), 0);
    CHECK_THROWS_WITH(vf::surface_from_cloud(surface_pcd(ground, &zeros), "flat.pcd"),
                      Catch::Contains("flat.pcd") && Catch::Contains("no model surface points") &&
                          Catch::Contains("0 (unknown) everywhere") && Catch::Contains("z > 50mm"));
    CHECK_THROWS_WITH(vf::surface_from_cloud(surface_pcd(ground), "bare.pcd"),
                      Catch::Contains("bare.pcd") && Catch::Contains("no label field"));
  }
}

TEST_CASE("--free-space through: surface with no return in its cells is not charged, ground seen through is",
          "[verify]") {
  const World w;
  const Isometry3d T = pose(0.5, 0.4, -0.3);
  // The pickup with the rear half of its body's top missing from the scan in every view (as
  // under a crown that detect's crop cut away): no point at all in those cells.
  auto cand = candidate(sample(pickup(), 0.1, 0.05), pickup(), T);
  const Isometry3d inv = T.inverse();
  vf::Candidate occluded;
  for (std::size_t i = 0; i < cand.points.size(); ++i) {
    const Vector3d m = inv * cand.points[i];
    if (m.x() < 0 && m.z() > 0.95) continue;
    occluded.points.push_back(cand.points[i]);
    occluded.normals.push_back(cand.normals[i]);
    occluded.sensor.push_back(cand.sensor[i]);
  }
  REQUIRE(occluded.points.size() < cand.points.size() - 300);
  vf::Params unseen, through;
  through.free_space_through = true;
  const auto& model = w.models[0].surface;
  const vf::Check u = vf::Scorer(occluded, unseen).score(model, T);
  const vf::Check t = vf::Scorer(occluded, through).score(model, T);
  INFO("unseen " << u.violation << " " << u.score << ", through " << t.violation << " " << t.score);
  CHECK(u.violation > 0.3);  // half the tops expected and unseen
  // Those cells are empty: no evidence either way. Not 0: the cells along the missing top's
  // edges also hold ground past the footprint (a 75-degree view shifts z = 0 by 0.27 m), which
  // counts as seen through.
  CHECK(t.violation < u.violation - 0.15);
  CHECK(t.score > unseen.accept);
  CHECK(u.score < unseen.accept);
  // Complete scan: both modes see the same right answer.
  CHECK(vf::Scorer(cand, through).score(model, T).score > 0.9);
  // A rock under the pickup model: the ground around the rock is seen where the model's body
  // would be, so "through" still charges it and answers none.
  const std::vector<Box> rock{{{-0.8, -0.6, 0.0}, {0.8, 0.6, 0.9}}};
  const auto rock_cand = candidate(sample(rock, 0.1, 0.05), rock, pose(0.4, 0.3, 0.2));
  const auto m = match({"pickup", "flatbed"}, {graph(pickup()), graph(flatbed())}, false);
  const doc::SegmentGraph object;
  const canopy::documents::Verdict v = vf::run(through, {&rock_cand, &object, &m, &w.models});
  CHECK(v.model.empty());
  for (const auto& h : v.hypotheses) CHECK(h.free_space_violation > 0.3);
}

namespace {

// A boxy van: a 5 x 2 m body 2.2 m high on 0.4 m of wheels (the wheels as two axles' blocks)
// and a 0.8 m bonnet 1.1 m high at the front; and the container-like box of its body's size
// standing on the ground (no bonnet, no gap under it).
std::vector<Box> boxy_van() {
  return {{{-2.5, -1.0, 0.4}, {2.5, 1.0, 2.2}},
          {{2.5, -1.0, 0.4}, {3.3, 1.0, 1.1}},
          {{1.6, -1.0, 0.0}, {2.4, 1.0, 0.4}},
          {{-2.4, -1.0, 0.0}, {-1.6, 1.0, 0.4}}};
}
std::vector<Box> container_box() { return {{{-2.6, -1.0, 0.0}, {3.0, 1.0, 2.3}}}; }

}  // namespace

TEST_CASE("null hypothesis: a plain box of the candidate's extent", "[verify][box]") {
  const std::vector<vf::Model> models{{"van", graph(boxy_van()), sample(boxy_van(), 0.1), ""}};
  const auto m = match({"van"}, {graph(boxy_van())}, false);
  const doc::SegmentGraph object;  // no pairs: the principal-axis start
  SECTION("the box recovers the candidate's extent and heading") {
    const Isometry3d T = pose(0.6, 1.0, -0.5);
    const auto cand = candidate(sample(container_box(), 0.1, 0.05), container_box(), T);
    const vf::Scorer scorer(cand, vf::Params{});
    vf::Surface box;
    Isometry3d start;
    REQUIRE(vf::null_box(scorer.above_points(), 0.1, &box, &start));
    // Centre (0.2, 0) of the 5.6 x 2 m box in its frame, heading 0.6 (or turned by 180 deg).
    const Vector3d c = T * Vector3d(0.2, 0, 0);
    CHECK((start.translation() - Vector3d(c.x(), c.y(), 0)).norm() < 0.1);
    const double dh =
        std::remainder(std::atan2(start.linear()(1, 0), start.linear()(0, 0)) - 0.6, canopy::common::kPi);
    CHECK(std::abs(dh) < 0.02);
    Vector3d lo = box.points[0], hi = box.points[0];
    for (const auto& p : box.points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    // Extent to within the percentile cut and the sampling (points above the 0.3 m cut: the
    // top is the 99th percentile of z).
    CHECK(std::abs((hi.x() - lo.x()) - 5.6) < 0.25);
    CHECK(std::abs((hi.y() - lo.y()) - 2.0) < 0.25);
    CHECK(std::abs(hi.z() - 2.3) < 0.1);
    CHECK(vf::null_box({}, 0.1, &box, &start) == false);
  }
  SECTION("a container is answered as the van without the box, none with it") {
    const Isometry3d T = pose(-0.4, 0.5, 0.3);
    const auto cand = candidate(sample(container_box(), 0.1, 0.05), container_box(), T);
    vf::Params off;
    off.box = false;
    const doc::Verdict without = vf::run(off, {&cand, &object, &m, &models});
    CHECK(without.model == "van");  // the van's body explains the container
    CHECK(!without.box);
    const doc::Verdict with = vf::run(vf::Params{}, {&cand, &object, &m, &models});
    REQUIRE(with.box);
    CHECK(with.box->score > 0.9);
    CHECK(with.box->score > with.hypotheses[0].score + 0.1);
    CHECK(with.model.empty());
    CHECK(with.chosen == -1);
    CHECK(with.hypotheses[0].score == without.hypotheses[0].score);  // only the decision differs
  }
  SECTION("the van itself beats the box and is answered") {
    const Isometry3d T = pose(1.1, -0.7, 0.2);
    const auto cand = candidate(sample(boxy_van(), 0.1, 0.05), boxy_van(), T);
    const doc::Verdict v = vf::run(vf::Params{}, {&cand, &object, &m, &models});
    REQUIRE(v.box);
    CHECK(v.model == "van");
    CHECK(v.hypotheses[0].score > 0.9);
    CHECK(v.box->score < v.hypotheses[0].score - 0.1);
  }
}

TEST_CASE("sample_spacing: the median nearest-neighbour distance", "[verify][seen]") {
  std::vector<Vector3d> grid;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 6; ++j) grid.emplace_back(0.3 * i, 0.3 * j, 1.0);
  }
  CHECK(vf::sample_spacing(grid) == Approx(0.3).margin(1e-6));
  // One stray point far off does not move the median.
  grid.emplace_back(50, 50, 50);
  CHECK(vf::sample_spacing(grid) == Approx(0.3).margin(1e-6));
  CHECK(vf::sample_spacing({}) == 0);
  CHECK(vf::sample_spacing({Vector3d(1, 2, 3)}) == 0);
}

TEST_CASE("--seen-spacing: a coarsely sampled vehicle is not charged for the gaps between its samples",
          "[verify][seen]") {
  const World w;
  const Isometry3d T = pose(0.5, 0.4, -0.3);
  const auto& model = w.models[0].surface;  // the pickup, sampled every 0.1 m
  vf::Params off, on;
  off.seen_spacing = 0;
  on.seen_spacing = 1;
  // The pickup and the ground around it sampled every 0.3 m (the density rule's fitvox voxel at
  // ~55 object points/m² is 333 mm; its samples' median spacing 0.3 m), on a grid shifted by
  // half a spacing, with three samples in ten missing as fitvox drops voxels of too few points
  // (a fixed scatter): its own model at the true pose.
  vf::Surface thin;
  const vf::Surface grid = sample(pickup(), 0.3, 0.15);
  for (std::size_t i = 0; i < grid.points.size(); ++i) {
    if (((i * 2654435761u) >> 7) % 10 < 3) continue;
    thin.points.push_back(grid.points[i]);
    thin.normals.push_back(grid.normals[i]);
  }
  const auto coarse = candidate(thin, pickup(), T, 0.3);
  const vf::Scorer s_off(coarse, off), s_on(coarse, on);
  CHECK(s_off.seen_radius() == Approx(0.25));
  CHECK(s_on.seen_radius() == Approx(0.3).margin(0.01));
  const vf::Check c_off = s_off.score(model, T), c_on = s_on.score(model, T);
  INFO("off: explained " << c_off.explained << " violation " << c_off.violation << "; on: " << c_on.explained
                         << " " << c_on.violation);
  // Before: over a fifth of the model surface lies farther than 0.25 m from every sample and
  // counts as free space the sensor saw through (the scatter's holes: a surface point can be
  // 0.3-0.4 m from its nearest sample there).
  CHECK(c_off.violation > 0.2);
  // With the candidate's own spacing: the same explained share, half the charge gone.
  CHECK(c_on.explained == c_off.explained);
  CHECK(c_on.violation < 0.15);
  CHECK(c_on.violation < c_off.violation - 0.1);
  CHECK(c_on.score > c_off.score + 0.1);
  // A densely sampled candidate (0.1 m < --inlier-radius): the radius stays 0.25 m, the check
  // is the same number for number.
  const auto dense = candidate(sample(pickup(), 0.1, 0.05), pickup(), T);
  const vf::Scorer d_off(dense, off), d_on(dense, on);
  CHECK(d_on.seen_radius() == 0.25);
  const vf::Check e_off = d_off.score(model, T), e_on = d_on.score(model, T);
  CHECK(e_on.violation == e_off.violation);
  CHECK(e_on.score == e_off.score);
  // A rock sampled as coarsely, under the pickup model: the ground is seen where the pickup's
  // body would be, so it is still charged and the answer is none.
  const std::vector<Box> rock{{{-0.8, -0.6, 0.0}, {0.8, 0.6, 0.9}}};
  const auto rock_cand = candidate(sample(rock, 0.35, 0.175), rock, pose(0.4, 0.3, 0.2), 0.35);
  const auto m = match({"pickup", "flatbed"}, {graph(pickup()), graph(flatbed())}, false);
  const doc::SegmentGraph object;
  const canopy::documents::Verdict v = vf::run(on, {&rock_cand, &object, &m, &w.models});
  CHECK(v.model.empty());
  for (const auto& h : v.hypotheses) CHECK(h.free_space_violation > 0.3);
}

TEST_CASE("--seen-spacing is checked", "[verify][seen]") {
  vf::Params p;
  p.seen_spacing = -0.1;
  CHECK_THROWS_AS(vf::validate(p), canopy::common::UsageError);
  p.seen_spacing = 11;
  CHECK_THROWS_AS(vf::validate(p), canopy::common::UsageError);
  p.seen_spacing = 0;
  CHECK_NOTHROW(vf::validate(p));
}

namespace {

// A pose as a match result carries it (baseline --hypotheses): row-major 4 x 4, model -> candidate.
std::array<double, 16> row_major(const Isometry3d& T) {
  std::array<double, 16> a{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) a[static_cast<std::size_t>(4 * r + c)] = T.matrix()(r, c);
  }
  return a;
}

// FPFH-style hypotheses: the ranking without segment pairs, the first model with `given`.
doc::MatchResult posed_match(const Isometry3d& given) {
  auto m = match({"pickup", "flatbed"}, {graph(pickup()), graph(flatbed())}, false);
  for (auto& e : m.models) e.pairs.clear();
  m.models[0].pose = row_major(given);
  return m;
}

}  // namespace

TEST_CASE("a match result's pose is the start: the true pose, without pairs, is answered at the truth",
          "[verify]") {
  const World w;
  const Isometry3d T = pose(0.7, 1.2, -0.4);
  const auto cand = candidate(sample(pickup(), 0.1, 0.05), pickup(), T);
  const doc::SegmentGraph object;  // no graph: the match has no pairs
  const auto m = posed_match(T);
  SECTION("without ICP the given pose is scored as it is, and wins") {
    vf::Params p;
    p.icp_iterations = 0;
    const doc::Verdict v = vf::run(p, {&cand, &object, &m, &w.models});
    REQUIRE(v.model == "pickup");
    const auto& h = v.hypotheses.at(0);
    CHECK(h.start == "pose");
    CHECK_FALSE(h.flipped);
    const Isometry3d P = fm::to_isometry(h.pose);
    CHECK((P.matrix() - T.matrix()).norm() < 1e-12);
    CHECK(h.explained > 0.9);
    CHECK(h.flip_score < h.score - 0.2);  // its 180-degree flip was tried and lost
  }
  SECTION("with ICP (the defaults): the answer and its pose, to 1 mm and 0.1 degree") {
    const doc::Verdict v = vf::run(vf::Params{}, {&cand, &object, &m, &w.models});
    REQUIRE(v.model == "pickup");
    const Isometry3d P = fm::to_isometry(v.hypotheses.at(0).pose);
    CHECK((P.translation() - T.translation()).norm() < 1e-3);
    CHECK(angle_deg(P, T) < 0.1);
    CHECK(v.hypotheses.at(1).score < v.hypotheses.at(0).score - 0.3);  // flatbed, no pose: axes only
    CHECK(v.hypotheses.at(1).start.rfind("axes", 0) == 0);
  }
}

TEST_CASE("a given pose turned round is set right by its flip; --no-flip does not try it", "[verify]") {
  const World w;
  const Isometry3d T = pose(-1.1, 0.4, 0.9);
  const auto cand = candidate(sample(pickup(), 0.1, 0.05), pickup(), T);
  const doc::SegmentGraph object;
  // The truth turned by 180 degrees about the vertical through the posed model's centre.
  Vector3d centre = Vector3d::Zero();
  for (const auto& q : w.models[0].surface.points) centre += q;
  centre /= static_cast<double>(w.models[0].surface.points.size());
  const Isometry3d F = Eigen::Translation3d(T * centre) *
                       Eigen::AngleAxisd(canopy::common::kPi, Vector3d::UnitZ()) *
                       Eigen::Translation3d(-(T * centre)) * T;
  const auto m = posed_match(F);
  vf::Params p;
  p.icp_iterations = 0;
  const doc::Verdict v = vf::run(p, {&cand, &object, &m, &w.models});
  REQUIRE(v.model == "pickup");
  CHECK(v.hypotheses[0].start == "pose-flipped");
  CHECK(v.hypotheses[0].flipped);
  CHECK((fm::to_isometry(v.hypotheses[0].pose).matrix() - T.matrix()).norm() < 1e-9);
  p.flip = false;
  const doc::Verdict nf = vf::run(p, {&cand, &object, &m, &w.models});
  // Without the flip the given pose (turned round) loses to the principal axes' start.
  CHECK(nf.hypotheses[0].start == "axes");
  CHECK(nf.hypotheses[0].flip_score == 0);  // no flip was scored
}

TEST_CASE("a given pose far off: the principal-axis start still recovers the model", "[verify]") {
  const World w;
  const Isometry3d T = pose(2.2, -0.6, 0.3);
  const auto cand = candidate(sample(pickup(), 0.1, 0.05), pickup(), T);
  const doc::SegmentGraph object;
  // 40 m away and turned: no candidate point within ICP's reach of the posed model.
  const auto m = posed_match(pose(0.5, 30, -25));
  const doc::Verdict v = vf::run(vf::Params{}, {&cand, &object, &m, &w.models});
  REQUIRE(v.model == "pickup");
  const auto& h = v.hypotheses.at(0);
  CHECK(h.start.rfind("axes", 0) == 0);
  const Isometry3d P = fm::to_isometry(h.pose);
  CHECK((P.translation() - T.translation()).norm() < 1e-3);
  CHECK(angle_deg(P, T) < 0.1);
  // The far pose itself, scored where it is, explains nothing.
  const vf::Scorer scorer(cand, vf::Params{});
  CHECK(scorer.score(w.models[0].surface, pose(0.5, 30, -25)).explained == 0);
}

TEST_CASE("a pose leaning beyond --max-tilt from the tile's vertical scores 0 and is marked tilted",
          "[verify][tilt]") {
  // The candidate is an upright pickup in its own frame; the frame's transform to the tile leans
  // it by `lean` about x, so every pose verify finds (upright in the candidate's frame) leans by
  // that much in the tile: a vehicle on its side, on its nose, upside down, which no parked
  // vehicle is (docs/decisions/verify.md §21).
  const World w;
  const Isometry3d T = pose(0.7, 1.2, -0.4);
  const auto cand = candidate(sample(pickup(), 0.1, 0.05), pickup(), T);
  const doc::SegmentGraph object;
  const auto m = posed_match(T);
  const auto to_tile = [](double lean_deg) {
    Isometry3d L = Isometry3d::Identity();
    L.linear() = Eigen::AngleAxisd(lean_deg * canopy::common::kPi / 180, Vector3d::UnitX()).toRotationMatrix();
    return L;
  };
  vf::Params p;  // max-tilt 40 degrees
  REQUIRE(std::abs(p.max_tilt - 40 * canopy::common::kPi / 180) < 1e-12);
  SECTION("leaning 30 degrees (within the bound): answered, nothing tilted") {
    const Isometry3d L = to_tile(30);
    const doc::Verdict v = vf::run(p, {&cand, &object, &m, &w.models, &L});
    REQUIRE(v.model == "pickup");
    for (const auto& h : v.hypotheses) CHECK_FALSE(h.tilted);
    const double lean =
        std::acos(fm::to_isometry(*v.hypotheses[0].pose_tile).linear()(2, 2)) * 180 / canopy::common::kPi;
    CHECK(std::abs(lean - 30) < 0.1);
  }
  SECTION("on its side (90 degrees): every hypothesis tilted, score 0, its measures kept; none") {
    const Isometry3d L = to_tile(90);
    const doc::Verdict v = vf::run(p, {&cand, &object, &m, &w.models, &L});
    CHECK(v.model.empty());
    for (const auto& h : v.hypotheses) {
      CHECK(h.tilted);
      CHECK(h.score == 0);
    }
    CHECK(v.hypotheses[0].explained > 0.9);  // the pose fits; it is not a vehicle's
    // Written only when true, and read back.
    doc::Verdict named = v;
    named.candidate = "samples.pcd";
    const std::string text = doc::serialize_verdict(named);
    CHECK(text.find("\"tilted\": true") != std::string::npos);
    CHECK(doc::parse_verdict(text, "v.json").hypotheses[0].tilted);
    // No bound (180, the ablation): the same pose answered.
    p.max_tilt = canopy::common::kPi;
    const doc::Verdict free = vf::run(p, {&cand, &object, &m, &w.models, &L});
    CHECK(free.model == "pickup");
    CHECK(doc::serialize_verdict(free).find("tilted") == std::string::npos);
  }
  SECTION("on its side, with classes: no class and no nearest instance from a pose ruled out") {
    const Isometry3d L = to_tile(90);
    std::vector<vf::Model> classed = w.models;
    classed[0].vehicle_class = "pickup-truck";
    classed[1].vehicle_class = "truck";
    const doc::Verdict v = vf::run(p, {&cand, &object, &m, &classed, &L});
    REQUIRE(v.has_classes);
    CHECK(v.model.empty());
    CHECK(v.vehicle_class.empty());
    CHECK(v.nearest_instance.empty());
    // the same none confidence as for any best score of 0 (the tilted ones' scores)
    CHECK(v.confidence > 0);
    CHECK(v.confidence < 1);
    // upright, the class is the answer's
    const doc::Verdict up = vf::run(p, {&cand, &object, &m, &classed});
    CHECK(up.vehicle_class == "pickup-truck");
    CHECK(up.nearest_instance == "pickup");
  }
  SECTION("on its side with --accept 0 and no box (every best answered): a tilted one still is not") {
    const Isometry3d L = to_tile(90);
    p.accept = 0;
    p.box = false;
    const doc::Verdict v = vf::run(p, {&cand, &object, &m, &w.models, &L});
    REQUIRE(v.hypotheses.at(0).tilted);
    CHECK(v.model.empty());
    CHECK(v.chosen == -1);
    // upright (no transform), the same options answer it
    CHECK(vf::run(p, {&cand, &object, &m, &w.models}).model == "pickup");
  }
  SECTION("an upright start beats a better-fitting tilted one of the same hypothesis") {
    // The tile leans the candidate's frame 60 degrees: the principal-axis start (the true pose in the
    // candidate's frame) fits but leans 60 degrees in the tile; the given pose is the same pose
    // stood upright in the tile, a poor fit. No ICP, no flip: each start scored as it is.
    const Isometry3d L = to_tile(60);
    Isometry3d up = T;
    up.linear() = L.linear().transpose() * T.linear();
    const auto mu = posed_match(up);
    p.icp_iterations = 0;
    p.flip = false;
    const doc::Verdict v = vf::run(p, {&cand, &object, &mu, &w.models, &L});
    const auto& h = v.hypotheses.at(0);
    CHECK(h.start == "pose");
    CHECK_FALSE(h.tilted);
    // without the bound the better fit wins: the principal axes', leaning 60 degrees
    p.max_tilt = canopy::common::kPi;
    const doc::Verdict vfree = vf::run(p, {&cand, &object, &mu, &w.models, &L});
    const auto& free = vfree.hypotheses.at(0);
    INFO("upright " << h.score << ", tilted " << free.score);
    CHECK(free.start == "axes");
    CHECK_FALSE(free.tilted);
    CHECK(free.score > h.score + 0.2);
  }
  SECTION("no transform: the candidate's frame is the reference (upright here)") {
    const doc::Verdict v = vf::run(p, {&cand, &object, &m, &w.models});
    CHECK(v.model == "pickup");
    CHECK_FALSE(v.hypotheses[0].tilted);
  }
  SECTION("--max-tilt is checked") {
    for (const double bad_deg : {0.0, -5.0, 181.0}) {
      p.max_tilt = bad_deg * canopy::common::kPi / 180;
      CHECK_THROWS_AS(vf::validate(p), canopy::common::UsageError);
    }
    p.max_tilt = 180 * (canopy::common::kPi / 180);  // as --max-tilt=180 gives it
    CHECK_NOTHROW(vf::validate(p));
  }
}
