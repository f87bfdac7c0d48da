// fit_neighbourhood on analytic surfaces at random poses (thesis ch. 3 / ALGORITHMS.md §C).
#include <catch2/catch.hpp>

#include <cmath>

#include "canopy/common/rng.h"
#include "fitvox/fitvox.h"
#include "fixtures/fitvox_surfaces.h"

using namespace canopy;
using namespace fitvox_test;
using Eigen::Vector3d;

namespace {

constexpr double kHalf = 0.064;  // half of the 128 mm thesis voxel

bool finite(const fitvox::Fit& f) {
  bool ok = f.normal.allFinite() && f.u.allFinite() && f.v.allFinite() && f.w.allFinite() &&
            f.p.allFinite() && std::isfinite(f.rms) && std::isfinite(f.variation) &&
            std::isfinite(f.mean_curvature) && std::isfinite(f.gauss_curvature);
  for (double a : f.a) ok = ok && std::isfinite(a);
  return ok;
}

double angle_deg(const Vector3d& a, const Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

// The fitted biquadratic must reproduce each point within `tol` along w (checks the
// orientation flip of frame and coefficients, and the (q - p) local coordinates).
double max_model_error(const fitvox::Fit& f, const std::vector<Vector3d>& pts) {
  double worst = 0;
  for (const Vector3d& q : pts) {
    const Vector3d d = q - f.p;
    const double u = d.dot(f.u), v = d.dot(f.v), w = d.dot(f.w);
    const double m = f.a[0] * u * u + f.a[1] * u * v + f.a[2] * v * v + f.a[3] * u + f.a[4] * v + f.a[5];
    worst = std::max(worst, std::abs(w - m));
  }
  return worst;
}

void check_frame(const fitvox::Fit& f) {
  CHECK(f.u.norm() == Approx(1).margin(1e-12));
  CHECK(f.v.norm() == Approx(1).margin(1e-12));
  CHECK(std::abs(f.u.dot(f.v)) < 1e-12);
  CHECK((f.u.cross(f.v) - f.w).norm() < 1e-12);  // right-handed
  CHECK(f.normal.norm() == Approx(1).margin(1e-12));
}

}  // namespace

TEST_CASE("plane at random poses: exact normal, zero curvature", "[fit][plane]") {
  common::Rng rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3d n = random_unit(rng);
    const Vector3d c(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(0, 20));
    const auto pts = plane_patch(c, n, kHalf, 100, rng);
    const Vector3d toward = (n + 0.5 * random_unit(rng)).normalized();  // any side-of-n view
    const auto f = fitvox::fit_neighbourhood(pts, nearest(pts, c), toward);
    REQUIRE(f.verdict == fitvox::Verdict::kKept);
    CHECK_FALSE(f.plane_fallback);
    check_frame(f);
    CHECK(angle_deg(f.normal, n) < 1e-6);  // faces the sensor side: n, not -n
    CHECK(std::abs(f.mean_curvature) < 1e-6);
    CHECK(std::abs(f.gauss_curvature) < 1e-6);
    CHECK(f.rms < 1e-9);
    CHECK(f.variation < 1e-12);
    CHECK(max_model_error(f, pts) < 1e-9);
  }
}

TEST_CASE("plane with noise: normal within the stated tolerance", "[fit][plane][noise]") {
  // sigma = 2 mm, 200 points over 128 mm: the biquadratic's slope at p has a standard error of
  // roughly 0.01 rad; 3 degrees is > 5 standard errors.
  common::Rng rng(12);
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3d n = random_unit(rng);
    const Vector3d c(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(0, 5));
    auto pts = plane_patch(c, n, kHalf, 200, rng);
    add_noise(&pts, 0.002, rng);
    const auto f = fitvox::fit_neighbourhood(pts, nearest(pts, c), n);
    REQUIRE(f.verdict == fitvox::Verdict::kKept);
    CHECK(angle_deg(f.normal, n) < 3.0);
    CHECK(f.rms == Approx(0.002).epsilon(0.2));  // RMS ~ sigma sqrt((k-6)/k)
  }
}

TEST_CASE("sphere at random poses: H = -1/R seen from outside, K = 1/R^2", "[fit][sphere]") {
  // Fourth-order terms the biquadratic cannot represent bias the curvature by ~(hw/R)^2:
  // 1.6 % at R = 0.5 m; tolerance 4 %. Normal: exact radial direction within 0.5 deg.
  common::Rng rng(13);
  for (int trial = 0; trial < 50; ++trial) {
    const double r = rng.uniform(0.5, 3.0);
    const Vector3d centre(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20));
    const Vector3d d = random_unit(rng);
    const auto pts = sphere_patch(centre, r, d, kHalf, 300, rng);
    const std::size_t ip = nearest(pts, centre + r * d);
    const Vector3d radial = (pts[ip] - centre).normalized();

    const auto out = fitvox::fit_neighbourhood(pts, ip, radial);  // sensor outside
    REQUIRE(out.verdict == fitvox::Verdict::kKept);
    check_frame(out);
    CHECK(angle_deg(out.normal, radial) < 0.5);
    CHECK(out.mean_curvature == Approx(-1 / r).epsilon(0.04));
    CHECK(out.gauss_curvature == Approx(1 / (r * r)).epsilon(0.08));
    CHECK(max_model_error(out, pts) < 2e-4);

    const auto in = fitvox::fit_neighbourhood(pts, ip, -radial);  // sensor inside: concave
    REQUIRE(in.verdict == fitvox::Verdict::kKept);
    check_frame(in);
    CHECK(angle_deg(in.normal, -radial) < 0.5);
    CHECK(in.mean_curvature == Approx(1 / r).epsilon(0.04));
    CHECK(in.gauss_curvature == Approx(1 / (r * r)).epsilon(0.08));
    CHECK(in.rms == Approx(out.rms).margin(1e-12));
  }
}

TEST_CASE("sphere with noise: curvature within the stated tolerance", "[fit][sphere][noise]") {
  // R = 0.5 m, sigma = 1 mm, 800 points: the standard error of H from a 128 mm patch is
  // about 0.05 /m (2.5 % of 1/R); tolerance 15 %.
  common::Rng rng(14);
  for (int trial = 0; trial < 30; ++trial) {
    const double r = 0.5;
    const Vector3d centre(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5));
    const Vector3d d = random_unit(rng);
    auto pts = sphere_patch(centre, r, d, kHalf, 800, rng);
    add_noise(&pts, 0.001, rng);
    const std::size_t ip = nearest(pts, centre + r * d);
    const auto f = fitvox::fit_neighbourhood(pts, ip, d);
    REQUIRE(f.verdict == fitvox::Verdict::kKept);
    CHECK(f.mean_curvature == Approx(-1 / r).epsilon(0.15));
    CHECK(angle_deg(f.normal, d) < 3.0);
  }
}

TEST_CASE("cylinder at random poses: K = 0, |H| = 1/(2R)", "[fit][cylinder]") {
  common::Rng rng(15);
  for (int trial = 0; trial < 50; ++trial) {
    const double r = rng.uniform(0.3, 2.0);
    const Vector3d ax = random_unit(rng);
    Vector3d d, e2;
    frame_for(ax, &d, &e2);
    const Vector3d c(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20));
    const auto pts = cylinder_patch(c, ax, r, d, kHalf, 300, rng);
    const std::size_t ip = nearest(pts, c + r * d);
    const Vector3d radial = (pts[ip] - c - (pts[ip] - c).dot(ax) * ax).normalized();
    const auto f = fitvox::fit_neighbourhood(pts, ip, radial);
    REQUIRE(f.verdict == fitvox::Verdict::kKept);
    check_frame(f);
    CHECK(angle_deg(f.normal, radial) < 0.5);
    // K of the exact cylinder is 0; the fit's K stays below 2 % of 1/R^2.
    CHECK(std::abs(f.gauss_curvature) < 0.02 / (r * r));
    CHECK(f.mean_curvature == Approx(-1 / (2 * r)).epsilon(0.04));
  }
}

TEST_CASE("degenerate neighbourhoods give no NaN", "[fit][degenerate]") {
  common::Rng rng(16);
  const Vector3d z = Vector3d::UnitZ();
  SECTION("empty, one and two points") {
    std::vector<Vector3d> pts;
    CHECK(fitvox::fit_neighbourhood(pts, 0, z).verdict == fitvox::Verdict::kDegenerate);
    pts.push_back({1, 2, 3});
    auto f = fitvox::fit_neighbourhood(pts, 0, z);
    CHECK(f.verdict == fitvox::Verdict::kDegenerate);
    CHECK(finite(f));
    pts.push_back({1.01, 2, 3});
    f = fitvox::fit_neighbourhood(pts, 1, z);
    CHECK(f.verdict == fitvox::Verdict::kDegenerate);
    CHECK(finite(f));
  }
  SECTION("coincident points") {
    std::vector<Vector3d> pts(50, Vector3d(0.5, 0.5, 0.5));
    const auto f = fitvox::fit_neighbourhood(pts, 0, z);
    CHECK(f.verdict == fitvox::Verdict::kDegenerate);
    CHECK(finite(f));
  }
  SECTION("collinear points (one scan line)") {
    std::vector<Vector3d> pts;
    const Vector3d dir = random_unit(rng);
    for (int i = 0; i < 64; ++i) pts.push_back(Vector3d(3, 4, 5) + rng.uniform(-0.06, 0.06) * dir);
    const auto f = fitvox::fit_neighbourhood(pts, 0, z);
    CHECK(f.verdict == fitvox::Verdict::kDegenerate);
    CHECK(finite(f));
  }
  SECTION("five points: plane fallback") {
    const Vector3d n = random_unit(rng);
    const auto pts = plane_patch(Vector3d(1, 1, 1), n, kHalf, 5, rng);
    const auto f = fitvox::fit_neighbourhood(pts, 0, n);
    REQUIRE(f.verdict == fitvox::Verdict::kKept);
    CHECK(f.plane_fallback);
    CHECK(finite(f));
    CHECK(angle_deg(f.normal, n) < 1e-6);
  }
  SECTION("points on a circle: biquadratic undetermined, plane fallback") {
    // u² + v² = r² makes the columns u², v², 1 dependent (ALGORITHMS.md §C.3).
    const Vector3d n = random_unit(rng);
    Vector3d t1, t2;
    frame_for(n, &t1, &t2);
    std::vector<Vector3d> pts;
    for (int i = 0; i < 40; ++i) {
      const double th = 2 * M_PI * i / 40;
      pts.push_back(Vector3d(2, 2, 2) + 0.05 * (std::cos(th) * t1 + std::sin(th) * t2));
    }
    const auto f = fitvox::fit_neighbourhood(pts, 3, n);
    REQUIRE(f.verdict == fitvox::Verdict::kKept);
    CHECK(f.plane_fallback);
    CHECK(finite(f));
    CHECK(angle_deg(f.normal, n) < 1e-6);
    CHECK(f.a[0] == 0);
    CHECK(f.gauss_curvature == 0);
  }
}
