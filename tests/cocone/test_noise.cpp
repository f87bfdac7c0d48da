// Issue 19: noisy scans of shapes of known area through fitvox (resampling, default) and cocone.
// Dense points on a sphere and a closed box with isotropic Gaussian noise of a quarter of the
// sample spacing (sigma = 32 mm, 128 mm voxels: the thesis's worst level) must give a Cocone
// surface within 5% of the true area that drops at most 1% of the samples.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "cocone/cocone.h"
#include "fitvox/fitvox.h"

using namespace canopy;
using Eigen::Vector3d;

namespace {

struct Outcome {
  double area = 0;
  std::size_t samples = 0, dropped = 0;
};

// fitvox (default parameters: noise estimated, resampling on) -> cocone (no thesis post-processing).
Outcome reconstruct(const fitvox::Scan& scan, bool resample) {
  fitvox::Params fp;
  fp.resample = resample;
  const fitvox::Result r = fitvox::run(fp, scan);
  std::vector<Vector3d> pts, normals;
  for (const auto& s : r.samples) {
    pts.push_back(s.fit.p);
    normals.push_back(s.fit.normal);
  }
  const cocone::Surface surf = cocone::reconstruct(pts, normals, cocone::CoconeParams{});
  Outcome o;
  o.samples = pts.size();
  std::set<std::int32_t> used;
  for (const auto& f : surf.faces) {
    o.area += 0.5 * (pts[f[1]] - pts[f[0]]).cross(pts[f[2]] - pts[f[0]]).norm();
    used.insert(f.begin(), f.end());
  }
  o.dropped = pts.size() - used.size();
  return o;
}

// Uniform random points on the surface (`density` per m²), noise sigma, sensor = outward normal.
template <class Sampler>
fitvox::Scan noisy(Sampler sample, double area, double density, double sigma, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, sigma);
  fitvox::Scan scan;
  const auto n = static_cast<std::size_t>(area * density);
  for (std::size_t i = 0; i < n; ++i) {
    Vector3d p, normal;
    sample(rng, p, normal);
    scan.points.push_back(p + Vector3d(g(rng), g(rng), g(rng)));
    scan.sensor.push_back(normal);
  }
  return scan;
}

}  // namespace

TEST_CASE("noisy sphere (sigma = 1/4 sample spacing): area within 5%, at most 1% of samples dropped") {
  const double R = 1.5, area = 4 * M_PI * R * R;
  const Vector3d c(0.3, -0.2, 2.0);
  auto sphere = [&](std::mt19937_64& rng, Vector3d& p, Vector3d& n) {
    std::normal_distribution<double> g(0, 1);
    n = Vector3d(g(rng), g(rng), g(rng)).normalized();
    p = c + R * n;
  };
  for (unsigned seed : {1u, 2u}) {
    const fitvox::Scan scan = noisy(sphere, area, 8000, 0.032, seed);
    const Outcome o = reconstruct(scan, true);
    INFO("seed " << seed << ": area " << o.area << " of " << area << ", dropped " << o.dropped << " of "
                 << o.samples);
    CHECK(std::abs(o.area - area) <= 0.05 * area);
    CHECK(o.dropped <= 0.01 * o.samples);
  }
}

// Vehicle-sized (5.0 x 2.5 x 2.0 m): 128 mm samples cannot reach the edges, so every mesh of
// them chamfers each edge by about (2 - sqrt 2) x 87 mm of area per metre, noise or not (a
// 2.4 x 1.6 x 1.2 m box loses 6% noise-free, 4% of that here). The noise must add no loss
// beyond 2% of the noise-free reconstruction.
TEST_CASE("noisy closed box (sigma = 1/4 sample spacing): area within 5%, at most 1% of samples dropped") {
  const Vector3d lo(-2.5, -1.25, 0.5), size(5.0, 2.5, 2.0);
  const double faces[3] = {size.y() * size.z(), size.x() * size.z(), size.x() * size.y()};
  const double area = 2 * (faces[0] + faces[1] + faces[2]);
  auto box = [&](std::mt19937_64& rng, Vector3d& p, Vector3d& n) {
    std::uniform_real_distribution<double> u(0, 1);
    double pick = u(rng) * area / 2;
    int axis = 0;
    while (axis < 2 && pick > faces[axis]) pick -= faces[axis++];
    const bool high = u(rng) < 0.5;
    p = lo + Vector3d(u(rng) * size.x(), u(rng) * size.y(), u(rng) * size.z());
    p(axis) = lo(axis) + (high ? size(axis) : 0);
    n = Vector3d::Zero();
    n(axis) = high ? 1 : -1;
  };
  for (unsigned seed : {1u, 2u}) {
    const fitvox::Scan scan = noisy(box, area, 8000, 0.032, seed);
    const Outcome o = reconstruct(scan, true);
    const Outcome clean = reconstruct(noisy(box, area, 8000, 0.0, seed), true);
    INFO("seed " << seed << ": area " << o.area << " of " << area << " (noise-free " << clean.area
                 << "), dropped " << o.dropped << " of " << o.samples);
    CHECK(std::abs(o.area - area) <= 0.05 * area);
    CHECK(o.dropped <= 0.01 * o.samples);
    CHECK(std::abs(o.area - clean.area) <= 0.02 * clean.area);
  }
}

TEST_CASE("without resampling (the thesis's raw sample points) the noisy box loses samples") {
  // The measurement behind the default: the same 32 mm box drops over a quarter of its samples
  // as undersampled when each sample is a raw noisy point fitted in its voxel alone.
  const Vector3d lo(-2.5, -1.25, 0.5), size(5.0, 2.5, 2.0);
  const double faces[3] = {size.y() * size.z(), size.x() * size.z(), size.x() * size.y()};
  const double area = 2 * (faces[0] + faces[1] + faces[2]);
  auto box = [&](std::mt19937_64& rng, Vector3d& p, Vector3d& n) {
    std::uniform_real_distribution<double> u(0, 1);
    double pick = u(rng) * area / 2;
    int axis = 0;
    while (axis < 2 && pick > faces[axis]) pick -= faces[axis++];
    const bool high = u(rng) < 0.5;
    p = lo + Vector3d(u(rng) * size.x(), u(rng) * size.y(), u(rng) * size.z());
    p(axis) = lo(axis) + (high ? size(axis) : 0);
    n = Vector3d::Zero();
    n(axis) = high ? 1 : -1;
  };
  const Outcome raw = reconstruct(noisy(box, area, 8000, 0.032, 1), false);
  INFO("area " << raw.area << " of " << area << ", dropped " << raw.dropped << " of " << raw.samples);
  CHECK(raw.dropped > 0.1 * raw.samples);
  CHECK(raw.area < 0.9 * area);
}
