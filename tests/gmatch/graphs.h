// Hand-built and synthetic segment graphs for the gmatch tests and benchmark.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "canopy/common/rng.h"
#include "canopy/formats/json_io.h"

namespace gmatch_test {

using canopy::formats::Segment;
using canopy::formats::SegmentGraph;
using canopy::formats::Vec3;

// A flat rectangular face of sides a x b (m): area a*b, elongation min/max side (the ratio of
// the PCA radii of a uniform rectangle), a small thickness.
inline Segment face(int id, Vec3 centroid, Vec3 normal, double a, double b, double thickness = 0.02) {
  Segment s;
  s.segment_id = id;
  s.vertex_count = 100;
  s.area = a * b;
  s.thickness = thickness;
  s.elongation = std::min(a, b) / std::max(a, b);
  s.radii = {std::max(a, b) / std::sqrt(12.0), std::min(a, b) / std::sqrt(12.0),
             thickness * std::max(a, b) / std::sqrt(12.0)};
  s.centroid = centroid;
  s.normal = normal;
  return s;
}

// A two-box vehicle (body + cabin), heading +x, seen from above: 11 faces (no floor).
// length/width/body height of the body, cabin length/height on top, cabin offset along x.
inline SegmentGraph vehicle(double length = 4.5, double width = 1.8, double body = 0.7,
                            double cabin_length = 2.2, double cabin_height = 0.45, double cabin_x = 0.1,
                            double clearance = 0.3) {
  SegmentGraph g;
  const double top = clearance + body, cw = width - 0.2;
  const double cx0 = cabin_x - cabin_length / 2, cx1 = cabin_x + cabin_length / 2;
  const double hood = length / 2 - cx1, trunk = cx0 + length / 2;
  auto& s = g.segments;
  s.push_back(face(0, {cx1 + hood / 2, 0, top}, {0, 0, 1}, hood, width));
  s.push_back(face(1, {cx0 - trunk / 2, 0, top}, {0, 0, 1}, trunk, width));
  s.push_back(face(2, {cabin_x, 0, top + cabin_height}, {0, 0, 1}, cabin_length, cw));
  s.push_back(face(3, {0, width / 2, clearance + body / 2}, {0, 1, 0}, length, body));
  s.push_back(face(4, {0, -width / 2, clearance + body / 2}, {0, -1, 0}, length, body));
  s.push_back(face(5, {length / 2, 0, clearance + body / 2}, {1, 0, 0}, width, body));
  s.push_back(face(6, {-length / 2, 0, clearance + body / 2}, {-1, 0, 0}, width, body));
  s.push_back(face(7, {cabin_x, cw / 2, top + cabin_height / 2}, {0, 1, 0}, cabin_length, cabin_height));
  s.push_back(face(8, {cabin_x, -cw / 2, top + cabin_height / 2}, {0, -1, 0}, cabin_length, cabin_height));
  s.push_back(face(9, {cx1, 0, top + cabin_height / 2}, {1, 0, 0}, cw, cabin_height));
  s.push_back(face(10, {cx0, 0, top + cabin_height / 2}, {-1, 0, 0}, cw, cabin_height));
  return g;
}

// n segments of realistic vehicle-part sizes scattered in a 6 x 2.5 x 2 m box.
inline SegmentGraph random_graph(std::uint64_t seed, int n) {
  canopy::common::Rng rng(seed);
  SegmentGraph g;
  for (int i = 0; i < n; ++i) {
    Segment s;
    s.segment_id = i;
    s.vertex_count = 50;
    s.area = 0.05 + 2.0 * std::pow(rng.uniform(), 2.0);
    s.thickness = rng.uniform(0.005, 0.08);
    s.elongation = rng.uniform(0.15, 1.0);
    s.centroid = {rng.uniform(-3, 3), rng.uniform(-1.25, 1.25), rng.uniform(0.3, 2.3)};
    Vec3 n3{rng.normal(), rng.normal(), rng.normal()};
    const double len = std::sqrt(n3[0] * n3[0] + n3[1] * n3[1] + n3[2] * n3[2]);
    s.normal = {n3[0] / len, n3[1] / len, n3[2] / len};
    g.segments.push_back(s);
  }
  return g;
}

// Row-major 3x3 rotation: about z by heading, then about x by tilt (radians).
inline std::array<double, 9> rotation(double heading, double tilt) {
  const double c = std::cos(heading), s = std::sin(heading);
  const double ct = std::cos(tilt), st = std::sin(tilt);
  // Rx(tilt) * Rz(heading)
  return {c, -s, 0, ct * s, ct * c, -st, st * s, st * c, ct};
}

inline Vec3 rotate(const std::array<double, 9>& r, const Vec3& v) {
  return {r[0] * v[0] + r[1] * v[1] + r[2] * v[2], r[3] * v[0] + r[4] * v[1] + r[5] * v[2],
          r[6] * v[0] + r[7] * v[1] + r[8] * v[2]};
}

inline SegmentGraph transformed(SegmentGraph g, double heading, double tilt, Vec3 t) {
  const auto r = rotation(heading, tilt);
  for (auto& s : g.segments) {
    s.normal = rotate(r, s.normal);
    const Vec3 c = rotate(r, s.centroid);
    s.centroid = {c[0] + t[0], c[1] + t[1], c[2] + t[2]};
  }
  return g;
}

// Fisher-Yates with the project RNG (std::shuffle is implementation-defined).
inline SegmentGraph shuffled(SegmentGraph g, std::uint64_t seed) {
  canopy::common::Rng rng(seed);
  auto& s = g.segments;
  for (size_t i = s.size(); i > 1; --i) std::swap(s[i - 1], s[rng.below(i)]);
  return g;
}

inline SegmentGraph without(SegmentGraph g, const std::vector<int>& ids) {
  auto& s = g.segments;
  s.erase(std::remove_if(
              s.begin(), s.end(),
              [&](const Segment& x) { return std::find(ids.begin(), ids.end(), x.segment_id) != ids.end(); }),
          s.end());
  return g;
}

// Measurement noise: relative area noise, additive thickness/elongation/centroid noise and a
// small normal tilt, all Gaussian with the given standard deviations.
inline SegmentGraph perturbed(SegmentGraph g, std::uint64_t seed, double area_rel = 0.05, double shape = 0.01,
                              double position = 0.02, double normal = 0.02) {
  canopy::common::Rng rng(seed);
  for (auto& s : g.segments) {
    s.area *= std::max(0.2, 1 + area_rel * rng.normal());
    s.thickness = std::clamp(s.thickness + shape * rng.normal(), 0.0, 1.0);
    s.elongation = std::clamp(s.elongation + shape * rng.normal(), 0.0, 1.0);
    for (auto& c : s.centroid) c += position * rng.normal();
    Vec3 n = s.normal;
    for (auto& c : n) c += normal * rng.normal();
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    s.normal = {n[0] / len, n[1] / len, n[2] / len};
  }
  return g;
}

}  // namespace gmatch_test
