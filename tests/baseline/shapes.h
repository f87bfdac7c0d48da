// Analytic surfaces with outward normals for the baseline tests: a box and a lying cylinder,
// sampled on a regular grid (no floor), in the modelbase frame (ground z = 0).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "baseline/baseline.h"
#include "canopy/common/rng.h"
#include "canopy/formats/pcd.h"

namespace baseline_test {

using canopy::baseline::Cloud;

// A box of length l (x), width w (y), height h (z) standing on the ground at clearance c:
// the top and the four sides, samples every `step` m.
inline Cloud box(double l = 4.0, double w = 2.0, double h = 1.2, double c = 0.3, double step = 0.1) {
  Cloud out;
  auto add = [&](Eigen::Vector3d p, Eigen::Vector3d n) {
    out.points.push_back(p.cast<float>());
    out.normals.push_back(n.cast<float>());
  };
  for (double x = -l / 2 + step / 2; x < l / 2; x += step) {
    for (double y = -w / 2 + step / 2; y < w / 2; y += step) add({x, y, c + h}, {0, 0, 1});
    for (double z = c + step / 2; z < c + h; z += step) {
      add({x, w / 2, z}, {0, 1, 0});
      add({x, -w / 2, z}, {0, -1, 0});
    }
  }
  for (double y = -w / 2 + step / 2; y < w / 2; y += step) {
    for (double z = c + step / 2; z < c + h; z += step) {
      add({l / 2, y, z}, {1, 0, 0});
      add({-l / 2, y, z}, {-1, 0, 0});
    }
  }
  return out;
}

// A cylinder of radius r and length l lying along x, its axis at height r + c: the mantle
// (no end caps), samples every `step` m.
inline Cloud cylinder(double l = 4.0, double r = 0.8, double c = 0.3, double step = 0.1) {
  Cloud out;
  const int around = static_cast<int>(std::ceil(2 * M_PI * r / step));
  for (double x = -l / 2 + step / 2; x < l / 2; x += step) {
    for (int k = 0; k < around; ++k) {
      const double a = 2 * M_PI * (k + 0.5) / around;
      const Eigen::Vector3d n(0, std::cos(a), std::sin(a));
      const Eigen::Vector3d p(x, r * n.y(), r + c + r * n.z());
      out.points.push_back(p.cast<float>());
      out.normals.push_back(n.cast<float>());
    }
  }
  return out;
}

inline Eigen::Isometry3d pose(double heading, Eigen::Vector3d t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}

// The scene: `model` posed, with the points whose normal faces `hidden` removed (one side
// occluded), Gaussian noise of sigma m, and a ground grid below the ground cut.
inline Cloud scene(const Cloud& model, const Eigen::Isometry3d& T, Eigen::Vector3d hidden, double sigma,
                   std::uint64_t seed) {
  canopy::common::Rng rng(seed);
  Cloud out;
  for (std::size_t i = 0; i < model.points.size(); ++i) {
    const Eigen::Vector3d n = T.linear() * model.normals[i].cast<double>();
    if (n.dot(hidden) > 0.5) continue;
    Eigen::Vector3d p = T * model.points[i].cast<double>();
    for (int k = 0; k < 3; ++k) p[k] += sigma * rng.normal();
    out.points.push_back(p.cast<float>());
    out.normals.push_back(n.cast<float>());
  }
  const Eigen::Vector3d t = T.translation();
  for (double x = -4; x <= 4; x += 0.2) {
    for (double y = -4; y <= 4; y += 0.2) {
      out.points.push_back(Eigen::Vector3f(float(t.x() + x), float(t.y() + y), 0.0f));
      out.normals.push_back(Eigen::Vector3f(0, 0, 1));
    }
  }
  return out;
}

inline canopy::formats::PointCloud to_cloud(const Cloud& c) {
  canopy::formats::PointCloud pc;
  pc.resize(c.points.size());
  const char* names[6] = {"x", "y", "z", "normal_x", "normal_y", "normal_z"};
  for (int k = 0; k < 6; ++k) {
    auto& col = pc.add(names[k]);
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      col[i] = k < 3 ? c.points[i][k] : c.normals[i][k - 3];
    }
  }
  return pc;
}

}  // namespace baseline_test
