// Synthetic vehicle-like segment graphs and scenes for the gmatch benchmark and the decision
// measurements, until real graphs from ncut exist.
#pragma once

#include <cmath>
#include <vector>

#include "canopy/common/math.h"
#include "canopy/common/rng.h"
#include "fixtures/gmatch_graphs.h"

namespace gmatch_bench {

using namespace gmatch_test;

// A vehicle-like graph of n segments: heavy-tailed areas (a few big panels, many small
// pieces), normals clustered around the five visible box directions (+z, +-x, +-y) with up to
// ~20 degrees of tilt, centroids in a length x 2.2 x 2.5 m box, thin segments.
inline SegmentGraph synthetic_vehicle(std::uint64_t seed, int n, double length = 5.0) {
  canopy::common::Rng rng(seed);
  SegmentGraph g;
  const Vec3 dirs[5] = {{0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  SegmentDraw draw;
  draw.vertex_count = 40;
  draw.area_min = 0.03;
  draw.area_scale = 3.0;
  draw.area_power = 3.0;
  draw.thickness_hi = 0.05;
  draw.elongation_lo = 0.2;
  draw.lo = {-length / 2, -1.1, 0.3};
  draw.hi = {length / 2, 1.1, 2.8};
  for (int i = 0; i < n; ++i) {
    Segment s = random_segment(rng, i, draw);
    Vec3 d = dirs[rng.below(5)];
    for (auto& c : d) c += 0.2 * rng.normal();
    s.normal = normalized(d);
    g.segments.push_back(s);
  }
  return g;
}

struct SceneSpec {
  double drop = 0.2;             // share of segments occluded away
  int clutter = 5;               // foliage segments added (small, random normals)
  int splits = 2;                // largest segments over-segmented into two halves
  double area_noise = 0.1;       // relative
  double position_noise = 0.05;  // m
  double normal_noise = 0.05;    // ~3 degrees
  bool random_heading = true;    // else the model's heading (translation only)
  double flip = 0;               // share of normals with their sign flipped
};

// The model seen in a scene: occlusion, over-segmentation, clutter, noise, random heading.
inline SegmentGraph synthetic_scene(const SegmentGraph& model, std::uint64_t seed, const SceneSpec& spec = {}) {
  canopy::common::Rng rng(seed);
  SegmentGraph g;
  int next_id = 1000;
  std::vector<Segment> kept;
  for (const auto& s : model.segments) {
    if (rng.uniform() >= spec.drop) kept.push_back(s);
  }
  std::sort(kept.begin(), kept.end(), [](const Segment& a, const Segment& b) {
    return a.area > b.area || (a.area == b.area && a.segment_id < b.segment_id);
  });
  for (size_t i = 0; i < kept.size(); ++i) {
    Segment s = kept[i];
    if (static_cast<int>(i) < spec.splits) {
      Segment half = s;
      half.area = s.area / 2;
      half.elongation = std::min(1.0, s.elongation * 1.6);
      half.segment_id = next_id++;
      s.area /= 2;
      s.elongation = half.elongation;
      const double off = std::sqrt(s.area) / 2;
      s.centroid[0] += off;
      half.centroid[0] -= off;
      g.segments.push_back(half);
    }
    g.segments.push_back(s);
  }
  const auto clutter = random_graph(canopy::common::mix64(seed), spec.clutter);
  for (auto s : clutter.segments) {
    s.segment_id = next_id++;
    s.area = 0.02 + 0.2 * rng.uniform();
    g.segments.push_back(s);
  }
  g = perturbed(g, seed + 1, spec.area_noise, 0.01, spec.position_noise, spec.normal_noise);
  for (auto& s : g.segments) {
    if (rng.uniform() < spec.flip) s.normal = {-s.normal[0], -s.normal[1], -s.normal[2]};
  }
  const double heading = rng.uniform(-canopy::common::kPi, canopy::common::kPi);
  return transformed(g, spec.random_heading ? heading : 0.0, 0.0,
                     {rng.uniform(-50, 50), rng.uniform(-50, 50), 0.0});
}

}  // namespace gmatch_bench
