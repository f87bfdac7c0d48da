// fitvox::run: voxel partition, rejection rules, orientation, labels, overflow, determinism.
#include <catch2/catch.hpp>

#include <algorithm>
#include <map>

#include "canopy/common/error.h"
#include "canopy/common/rng.h"
#include "fitvox/fitvox.h"
#include "fixtures/fitvox_surfaces.h"

using namespace canopy;
using namespace fitvox_test;
using Eigen::Vector3d;

namespace {

// The parameters with Result::all filled too.
fitvox::Params keeping_all(fitvox::Params p) {
  p.keep_all = true;
  return p;
}

using Key = std::array<std::int32_t, 3>;

Key voxel_of(const Vector3d& q, double h) {
  return {static_cast<std::int32_t>(std::floor(q.x() / h + 0.5)),
          static_cast<std::int32_t>(std::floor(q.y() / h + 0.5)),
          static_cast<std::int32_t>(std::floor(q.z() / h + 0.5))};
}

// Points uniformly on the horizontal square [x0, x0+size]² at height z, density per m².
void add_floor(fitvox::Scan* s, double x0, double size, double z, double density, std::uint32_t label,
               common::Rng& rng) {
  const int n = static_cast<int>(size * size * density);
  for (int i = 0; i < n; ++i) {
    s->points.push_back({x0 + rng.uniform(0, size), x0 + rng.uniform(0, size), z});
    s->sensor.push_back(Vector3d(0.2, 0.1, 1).normalized());
    s->labels.push_back(label);
  }
}

// Points uniformly inside one voxel-sized cube (random scatter, e.g. leaves).
void add_scatter(fitvox::Scan* s, const Vector3d& lo, double edge, int n, std::uint32_t label,
                 common::Rng& rng) {
  for (int i = 0; i < n; ++i) {
    s->points.push_back(lo + Vector3d(rng.uniform(0, edge), rng.uniform(0, edge), rng.uniform(0, edge)));
    s->sensor.push_back(Vector3d::UnitZ());
    s->labels.push_back(label);
  }
}

void require_same(const fitvox::Result& a, const fitvox::Result& b) {
  REQUIRE(a.samples.size() == b.samples.size());
  for (std::size_t i = 0; i < a.samples.size(); ++i) {
    const auto &x = a.samples[i], &y = b.samples[i];
    REQUIRE(x.voxel == y.voxel);
    REQUIRE(x.source_index == y.source_index);
    REQUIRE(x.fit.normal == y.fit.normal);
    REQUIRE(x.fit.a == y.fit.a);
    REQUIRE(x.fit.rms == y.fit.rms);
  }
}

}  // namespace

TEST_CASE("partition: every point in exactly one voxel neighbourhood", "[run][partition]") {
  common::Rng rng(21);
  fitvox::Scan scan;
  add_floor(&scan, 0, 1.0, 0.06, 20000, 3, rng);
  for (int i = 0; i < 5000; ++i) {  // plus scattered points anywhere, incl. negative coords
    scan.points.push_back({rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)});
    scan.sensor.push_back(Vector3d::UnitZ());
    scan.labels.push_back(2);
  }
  fitvox::Params p;
  const auto r = fitvox::run(keeping_all(p), scan);
  std::map<Key, std::size_t> truth;
  for (const Vector3d& q : scan.points) ++truth[voxel_of(q, p.voxel)];
  REQUIRE(r.all.size() == truth.size());
  REQUIRE(r.stats.voxels == truth.size());
  std::size_t total = 0, i = 0;
  for (const auto& [key, count] : truth) {  // std::map order = lexicographic (i, j, k)
    const auto& s = r.all[i++];
    CHECK(s.voxel == key);
    CHECK(s.point_count == count);
    total += s.point_count;
    // the sample point lies in its own voxel and is the point nearest the centre
    CHECK(voxel_of(scan.points[s.source_index], p.voxel) == key);
  }
  CHECK(total == scan.points.size());
  CHECK(r.stats.kept + r.stats.too_few + r.stats.degenerate + r.stats.too_rough + r.stats.merged ==
        r.stats.voxels);
  // samples are the kept voxels, in the same (sorted) order
  REQUIRE(r.samples.size() == r.stats.kept);
  for (std::size_t j = 1; j < r.samples.size(); ++j) CHECK(r.samples[j - 1].voxel < r.samples[j].voxel);
}

TEST_CASE("without resampling the sample point is the input point nearest the voxel centre", "[run]") {
  common::Rng rng(22);
  fitvox::Scan scan;
  add_floor(&scan, -0.064, 0.128, 0.01, 20000, 3, rng);  // exactly voxel (0, 0, 0)
  scan.points.push_back({0, 0, 0});                      // exactly at its centre
  scan.sensor.push_back(Vector3d::UnitZ());
  scan.labels.push_back(1);
  fitvox::Params p;
  p.resample = false;
  const auto r = fitvox::run(keeping_all(p), scan);
  REQUIRE(r.samples.size() == 1);
  CHECK(r.samples[0].source_index == scan.points.size() - 1);
  CHECK(r.samples[0].fit.p == scan.points.back());
  CHECK(r.samples[0].label == 3);
  CHECK(r.samples[0].label_purity == Approx(1.0 - 1.0 / r.samples[0].point_count));
  CHECK(r.samples[0].sensor == scan.sensor.back());
}

TEST_CASE("sparse voxels are rejected at the min-points threshold", "[run][sparse]") {
  common::Rng rng(23);
  fitvox::Params p;
  for (int k : {31, 32}) {
    fitvox::Scan scan;
    // k points on a tilted plane inside voxel (0,0,0)
    for (int i = 0; i < k; ++i) {
      const double x = rng.uniform(-0.055, 0.055), y = rng.uniform(-0.055, 0.055);
      scan.points.push_back({x, y, 0.3 * x + 0.2 * y});
      scan.sensor.push_back(Vector3d::UnitZ());
    }
    const auto r = fitvox::run(p, scan);
    CHECK(r.samples.size() == (k >= p.min_points ? 1u : 0u));
    CHECK(r.stats.too_few == (k < p.min_points ? 1u : 0u));
  }
}

TEST_CASE("random scatter is rejected, surfaces kept", "[run][scatter]") {
  common::Rng rng(24);
  fitvox::Scan scan;
  add_floor(&scan, -0.064, 1.024, 0.06, 20000, 3, rng);  // 64 planar voxels
  for (int i = 0; i < 10; ++i) {                         // 10 scatter voxels above it, 200 pts each
    add_scatter(&scan, Vector3d(0.128 * i - 0.064, -0.064, 1.024 - 0.064), 0.128, 200, 2, rng);
  }
  for (double noise : {-1.0, 0.0}) {  // adaptive and fixed bound
    fitvox::Params p;
    p.noise = noise;
    const auto r = fitvox::run(keeping_all(p), scan);
    std::size_t floor_kept = 0, scatter_kept = 0;
    for (const auto& s : r.samples) (s.label == 3 ? floor_kept : scatter_kept)++;
    CHECK(floor_kept == 64);
    CHECK(scatter_kept == 0);
    CHECK(r.stats.too_rough == 10);
  }
}

TEST_CASE("normals face the sensor that saw the sample point", "[run][orientation]") {
  common::Rng rng(25);
  for (int trial = 0; trial < 20; ++trial) {
    fitvox::Scan scan;
    const Vector3d n = random_unit(rng);
    const Vector3d c(0, 0, 0);  // a voxel centre
    const auto pts = plane_patch(c, n, 0.04, 200, rng);
    const Vector3d sensor = (rng.uniform() < 0.5 ? 1.0 : -1.0) * (n + 0.3 * random_unit(rng)).normalized();
    for (const auto& q : pts) {
      scan.points.push_back(q);
      scan.sensor.push_back(sensor);
    }
    const auto r = fitvox::run(fitvox::Params{}, scan);
    REQUIRE(r.samples.size() == 1);
    const auto& f = r.samples[0].fit;
    CHECK(f.normal.dot(sensor) > 0);
    CHECK(std::abs(std::abs(f.normal.dot(n)) - 1) < 1e-9);
    CHECK((f.u.cross(f.v) - f.w).norm() < 1e-12);
  }
  SECTION("without sensor directions: toward +z") {
    fitvox::Scan scan;
    scan.points = plane_patch(Vector3d(0, 0, 0), Vector3d(0.3, 0, -1).normalized(), 0.04, 200, rng);
    const auto r = fitvox::run(fitvox::Params{}, scan);
    REQUIRE(r.samples.size() == 1);
    CHECK(r.samples[0].fit.normal.z() > 0);
    CHECK(r.samples[0].label == 0);
  }
}

TEST_CASE("majority label and purity", "[run][labels]") {
  common::Rng rng(26);
  fitvox::Scan scan;
  add_floor(&scan, -0.064, 0.128, 0.02, 20000, 1, rng);
  const std::size_t n1 = scan.points.size();
  for (std::size_t i = 0; i < n1 / 3; ++i) scan.labels[i] = 2;
  const auto r = fitvox::run(fitvox::Params{}, scan);
  REQUIRE(r.samples.size() == 1);
  CHECK(r.samples[0].label == 1);
  CHECK(r.samples[0].label_purity == Approx(double(n1 - n1 / 3) / n1));
}

TEST_CASE("voxel index overflow is an error", "[run][overflow]") {
  common::Rng rng(27);
  fitvox::Scan scan;
  add_floor(&scan, -0.064, 0.512, 0.02, 20000, 3, rng);
  SECTION("coordinate beyond 2^31 voxels") {
    scan.points.push_back({3e8, 0, 0});  // 2.3e9 voxels of 128 mm
    scan.sensor.push_back(Vector3d::UnitZ());
    scan.labels.push_back(0);
    CHECK_THROWS_AS(fitvox::run(fitvox::Params{}, scan), common::Error);
    CHECK_THROWS_WITH(fitvox::run(fitvox::Params{}, scan), Catch::Contains("overflow"));
  }
  SECTION("grid extent beyond 2^63 voxels") {
    for (double s : {-1.0, 1.0}) {
      scan.points.push_back({s * 2e8, s * 2e8, s * 2e8});
      scan.sensor.push_back(Vector3d::UnitZ());
      scan.labels.push_back(0);
    }
    CHECK_THROWS_WITH(fitvox::run(fitvox::Params{}, scan), Catch::Contains("overflow"));
  }
  SECTION("large but representable coordinates work (sorted path)") {
    for (double s : {-1.0, 1.0}) {
      scan.points.push_back({s * 1e5, s * 1e5, 0});
      scan.sensor.push_back(Vector3d::UnitZ());
      scan.labels.push_back(0);
    }
    const auto r = fitvox::run(keeping_all(fitvox::Params{}), scan);
    CHECK(r.stats.voxels > 16);
    CHECK(r.samples.size() == 16);  // the 4 x 4 floor voxels
  }
}

TEST_CASE("grid anchored at the origin: result independent of the bounding box", "[run][grid]") {
  common::Rng rng(28);
  fitvox::Scan scan;
  add_floor(&scan, -0.064, 0.512, 0.02, 20000, 3, rng);
  const auto a = fitvox::run(fitvox::Params{}, scan);
  scan.points.push_back({-7.3, 5.1, 2.2});  // a far point moves the bounding box
  scan.sensor.push_back(Vector3d::UnitZ());
  scan.labels.push_back(0);
  const auto b = fitvox::run(fitvox::Params{}, scan);
  require_same(a, b);
  REQUIRE(a.samples.size() == 16);
  CHECK(a.samples[0].voxel == Key{0, 0, 0});
}

TEST_CASE("thread count does not change the result", "[run][determinism]") {
  common::Rng rng(29);
  fitvox::Scan scan;
  add_floor(&scan, 0, 1.0, 0.06, 20000, 3, rng);
  add_noise(&scan.points, 0.004, rng);
  fitvox::Params p;
  const auto one = fitvox::run(p, scan);
  p.threads = 3;
  const auto three = fitvox::run(p, scan);
  require_same(one, three);
}

TEST_CASE("empty scan gives an empty result", "[run][degenerate]") {
  const auto r = fitvox::run(fitvox::Params{}, fitvox::Scan{});
  CHECK(r.samples.empty());
  CHECK(r.stats.voxels == 0);
}

TEST_CASE("mismatched optional columns and bad parameters are errors", "[run][errors]") {
  fitvox::Scan scan;
  scan.points = {{0, 0, 0}, {1, 1, 1}};
  scan.labels = {1};
  CHECK_THROWS_AS(fitvox::run(fitvox::Params{}, scan), common::Error);
  scan.labels.clear();
  fitvox::Params p;
  p.voxel = 0;
  CHECK_THROWS_AS(fitvox::run(p, scan), common::Error);
  p = fitvox::Params{};
  p.min_points = 5;
  CHECK_THROWS_AS(fitvox::run(p, scan), common::Error);
}

TEST_CASE("adaptive RMS bound follows the noise; the fixed thesis bound does not", "[run][adaptive]") {
  common::Rng rng(30);
  for (double sigma : {0.004, 0.016, 0.032}) {
    fitvox::Scan scan;
    add_floor(&scan, -0.064, 1.024, 0.0, 20000, 3, rng);  // 64 voxels, ~330 points each
    add_noise(&scan.points, sigma, rng);
    fitvox::Params p;
    const auto adaptive = fitvox::run(p, scan);
    // the estimate is the noise along the normal (the median of chi-square/dof is just below 1)
    // (at 32 mm the 128 mm voxel truncates the noise: the estimate is then lower)
    if (sigma < 0.02) CHECK(adaptive.stats.sigma_estimated == Approx(sigma).epsilon(0.1));
    CHECK(adaptive.samples.size() >= 60);
    p.noise = 0;
    const auto fixed = fitvox::run(p, scan);
    if (sigma > 0.008) CHECK(fixed.samples.empty());
  }
}

TEST_CASE("the RMS bound's range over the point counts: --max-rms at 6 points, a peak, then down",
          "[run][adaptive]") {
  fitvox::Params p;
  const double sigma = 0.01;
  // 6 points: a biquadratic fits them exactly, no noise term
  CHECK(fitvox::rms_bound(p, sigma, 6) == p.max_rms);
  const auto [least6, greatest6] = fitvox::rms_bound_range(p, sigma, 6, 400);
  CHECK(least6 == p.max_rms);
  CHECK(greatest6 > fitvox::rms_bound(p, sigma, 400));  // the peak lies inside the range
  CHECK(greatest6 == Approx(fitvox::rms_bound(p, sigma, 24)).epsilon(0.01));
  // from 32 points (the thesis's min-points) the bound only falls
  const auto [least32, greatest32] = fitvox::rms_bound_range(p, sigma, 32, 400);
  CHECK(least32 == fitvox::rms_bound(p, sigma, 400));
  CHECK(greatest32 == fitvox::rms_bound(p, sigma, 32));
  // no noise: --max-rms throughout
  const auto [least0, greatest0] = fitvox::rms_bound_range(p, 0, 6, 400);
  CHECK(least0 == p.max_rms);
  CHECK(greatest0 == p.max_rms);
}

TEST_CASE("resampling: the voxel's nearest point or centroid, on the fitted surface", "[run][resample]") {
  common::Rng rng(24);
  fitvox::Scan scan;
  add_floor(&scan, -0.064, 0.128, 0.01, 20000, 3, rng);  // voxel (0, 0, 0) only
  scan.points.push_back({0, 0, 0.01});                   // nearest to the centre
  scan.sensor.push_back(Vector3d::UnitZ());
  scan.labels.push_back(3);
  fitvox::Params centroid;
  centroid.from_centroid = true;
  const auto rc = fitvox::run(centroid, scan);
  REQUIRE(rc.samples.size() == 1);
  Vector3d c = Vector3d::Zero();
  for (const auto& q : scan.points) c += q;
  c /= static_cast<double>(scan.points.size());
  CHECK((rc.samples[0].fit.p - c).norm() < 1e-9);  // the centroid already lies on the plane
  const auto r = fitvox::run(keeping_all(fitvox::Params{}), scan);
  REQUIRE(r.samples.size() == 1);
  CHECK((r.samples[0].fit.p - scan.points.back()).norm() < 1e-9);
  CHECK(r.samples[0].fit.a[5] == Approx(0).margin(1e-9));
  CHECK(r.samples[0].fit.normal.dot(Vector3d::UnitZ()) == Approx(1));
  CHECK(r.stats.support == Approx(0.064));  // noise-free: half a voxel
}

TEST_CASE("resampling: a noisy plane on a voxel face gives one layer of samples, not two",
          "[run][resample]") {
  // z = 64 mm is the face between voxel layers 0 and 1: with sigma = 32 mm both layers hold
  // enough points, and each layer's fit is biased toward its own side by the truncation.
  common::Rng rng(25);
  fitvox::Scan scan;
  const double sigma = 0.032, size = 1.28;  // 10 x 10 voxel columns
  for (int i = 0; i < static_cast<int>(size * size * 20000); ++i) {
    scan.points.push_back(
        {rng.uniform(-0.064, size - 0.064), rng.uniform(-0.064, size - 0.064), 0.064 + sigma * rng.normal()});
    scan.sensor.push_back(Vector3d::UnitZ());
  }
  fitvox::Params thesis;
  thesis.resample = false;
  const auto raw = fitvox::run(thesis, scan);
  const auto res = fitvox::run(fitvox::Params{}, scan);
  auto spread = [](const fitvox::Result& r) {
    double s2 = 0;
    for (const auto& s : r.samples) s2 += (s.fit.p.z() - 0.064) * (s.fit.p.z() - 0.064);
    return std::sqrt(s2 / static_cast<double>(r.samples.size()));
  };
  INFO("thesis: " << raw.samples.size() << " samples, z spread " << spread(raw)
                  << "; resampled: " << res.samples.size() << " samples (" << res.stats.merged
                  << " merged), spread " << spread(res));
  CHECK(raw.samples.size() > 150);  // two layers over 100 columns
  CHECK(spread(raw) > 0.02);        // raw noisy points
  // One layer on the plane: most stacked pairs merge (a pair whose two nearest points lie more
  // than 32 mm apart in the plane stays, on the same surface: only denser there).
  CHECK(res.samples.size() <= 120);
  CHECK(res.stats.merged >= 80);
  CHECK(spread(res) < 0.005);  // on the plane
  // support = 6 sigma-hat (sigma-hat is low: each voxel sees a truncated half of the noise)
  CHECK(res.stats.support == Approx(std::clamp(6 * res.stats.sigma, 0.064, 0.128)));
  CHECK(res.stats.support > 0.1);
}

TEST_CASE("validate: the defaults pass; each bad parameter is a usage error naming its option") {
  CHECK_NOTHROW(fitvox::validate(fitvox::Params{}));
  auto with = [](auto change) {
    fitvox::Params p;
    change(p);
    return p;
  };
  CHECK_THROWS_WITH(fitvox::validate(with([](auto& p) { p.voxel = 0; })), Catch::StartsWith("--voxel"));
  CHECK_THROWS_WITH(fitvox::validate(with([](auto& p) { p.min_points = 5; })),
                    Catch::StartsWith("--min-points"));
  CHECK_THROWS_WITH(fitvox::validate(with([](auto& p) { p.noise = 1e9; })), Catch::StartsWith("--noise"));
  CHECK_THROWS_WITH(fitvox::validate(with([](auto& p) { p.support = 0; })), Catch::Contains("--support"));
  CHECK_THROWS_WITH(fitvox::validate(with([](auto& p) { p.merge = -1; })), Catch::StartsWith("--merge"));
  CHECK_THROWS_AS(fitvox::validate(with([](auto& p) { p.threads = 0; })), common::UsageError);
  // run() refuses the same parameters.
  CHECK_THROWS_AS(fitvox::run(with([](auto& p) { p.max_rms = -1; }), fitvox::Scan{}), common::UsageError);
}

TEST_CASE("the same samples for any thread count") {
  common::Rng rng(5);
  fitvox::Scan scan;
  for (int i = 0; i < 20000; ++i) {
    const double x = rng.uniform(-1, 1), y = rng.uniform(-1, 1);
    scan.points.emplace_back(x, y, 0.3 * x * x + 0.1 * y + 0.002 * rng.normal());
  }
  fitvox::Params p;
  const fitvox::Result one = fitvox::run(p, scan);
  p.threads = 3;
  const fitvox::Result three = fitvox::run(p, scan);
  REQUIRE(one.samples.size() > 100);
  REQUIRE(one.samples.size() == three.samples.size());
  for (std::size_t i = 0; i < one.samples.size(); ++i) {
    CHECK(one.samples[i].fit.p == three.samples[i].fit.p);
    CHECK(one.samples[i].fit.normal == three.samples[i].fit.normal);
  }
}
