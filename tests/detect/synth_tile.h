// Synthetic tiles for detect's tests and benchmark (header-only): terrain as a jittered point
// grid (flat, planar slope, rolling), vehicles as sampled boxes (top and four sides) posed on
// the terrain (pitched and rolled with it), trees (trunk + crown shell), bushes, boulders;
// ground truth labels (formats/labels.h; 4 = clutter) and vehicle instance ids; canopy
// occlusion (points under a crown are dropped with a probability), Gaussian noise, an
// optional georeferencing offset (UTM magnitudes) with float64 coordinates.
#pragma once

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "canopy/common/rng.h"
#include "canopy/formats/labels.h"
#include "canopy/formats/point_cloud.h"

namespace canopy::detect_test {

enum class Terrain { kFlat, kSlope, kRolling };

struct VehicleSpec {
  double x = 0, y = 0, heading = 0;  // tile frame before the offset; heading of the long axis (rad)
  double length = 4.5, width = 1.8, height = 1.5;
  std::uint32_t instance = 1;
  bool cabin = false;  // false: a box; true: a body to 55% of the height under a cabin
                       // (60% of the length, 75% of the width) up to the full height
};
struct TreeSpec {
  double x = 0, y = 0, crown_radius = 3, crown_base = 5, crown_top = 11, trunk_radius = 0.2;
};
struct BushSpec {
  double x = 0, y = 0, radius = 1.2, base = 0.2, top = 2.0;
};
struct BoulderSpec {
  double x = 0, y = 0, radius = 0.8;
};

struct TileSpec {
  double half_extent = 20;  // the tile is [-h, h]² (before the offset)
  Terrain terrain = Terrain::kFlat;
  double slope_deg = 15, slope_azimuth = 0.4;  // direction of steepest ascent (rad)
  double rolling_amplitude = 2, rolling_wavelength = 27;
  double base_height = 0;
  double spacing = 0.1;    // point spacing on every surface (m)
  double noise = 0;        // Gaussian sigma per axis (m)
  double occlusion = 0.6;  // probability a ground/vehicle point under a crown is hidden
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // added to every point (georeferencing)
  bool float64 = true;                               // x y z stored as F8 (else F4)
  std::uint64_t seed = 1;
  std::vector<VehicleSpec> vehicles;
  std::vector<TreeSpec> trees;
  std::vector<BushSpec> bushes;
  std::vector<BoulderSpec> boulders;
};

inline double ground_z(const TileSpec& s, double x, double y) {
  switch (s.terrain) {
    case Terrain::kFlat: return s.base_height;
    case Terrain::kSlope:
      return s.base_height + std::tan(s.slope_deg * M_PI / 180) *
                                 (x * std::cos(s.slope_azimuth) + y * std::sin(s.slope_azimuth));
    case Terrain::kRolling: {
      const double k = 2 * M_PI / s.rolling_wavelength;
      return s.base_height +
             s.rolling_amplitude * 0.5 * (std::sin(k * x + 0.3) + std::sin(0.8 * k * y + 1.1 + 0.4 * k * x));
    }
  }
  return 0;
}

inline Eigen::Vector3d ground_normal(const TileSpec& s, double x, double y) {
  const double e = 0.05;
  const double gx = (ground_z(s, x + e, y) - ground_z(s, x - e, y)) / (2 * e);
  const double gy = (ground_z(s, x, y + e) - ground_z(s, x, y - e)) / (2 * e);
  return Eigen::Vector3d(-gx, -gy, 1).normalized();
}

// The vehicle's frame: origin on the ground at its centre, z = terrain normal, x = heading.
inline Eigen::Matrix3d vehicle_rotation(const TileSpec& s, const VehicleSpec& v) {
  const Eigen::Vector3d n = ground_normal(s, v.x, v.y);
  Eigen::Vector3d ax(std::cos(v.heading), std::sin(v.heading), 0);
  ax = (ax - ax.dot(n) * n).normalized();
  Eigen::Matrix3d R;
  R.col(0) = ax;
  R.col(1) = n.cross(ax);
  R.col(2) = n;
  return R;
}
inline Eigen::Vector3d vehicle_centre(const TileSpec& s, const VehicleSpec& v) {
  return Eigen::Vector3d(v.x, v.y, ground_z(s, v.x, v.y)) + s.offset;
}

inline bool in_footprint(const VehicleSpec& v, double x, double y, double grow = 0) {
  const double dx = x - v.x, dy = y - v.y;
  const double u = dx * std::cos(v.heading) + dy * std::sin(v.heading);
  const double w = -dx * std::sin(v.heading) + dy * std::cos(v.heading);
  return std::abs(u) <= v.length / 2 + grow && std::abs(w) <= v.width / 2 + grow;
}

inline bool under_crown(const TileSpec& s, double x, double y) {
  for (const auto& t : s.trees) {
    if (std::hypot(x - t.x, y - t.y) < t.crown_radius) return true;
  }
  for (const auto& b : s.bushes) {
    if (std::hypot(x - b.x, y - b.y) < b.radius) return true;
  }
  return false;
}

// Share of the vehicle's top-view footprint under a crown or bush.
inline double canopy_cover(const TileSpec& s, const VehicleSpec& v) {
  int hidden = 0, total = 0;
  for (int a = 0; a < 20; ++a)
    for (int b = 0; b < 10; ++b) {
      const double u = (a + 0.5) / 20 - 0.5, w = (b + 0.5) / 10 - 0.5;
      const double x = v.x + u * v.length * std::cos(v.heading) - w * v.width * std::sin(v.heading);
      const double y = v.y + u * v.length * std::sin(v.heading) + w * v.width * std::cos(v.heading);
      hidden += under_crown(s, x, y);
      ++total;
    }
  return double(hidden) / total;
}

class TileBuilder {
 public:
  explicit TileBuilder(const TileSpec& s) : s_(s), rng_(common::derive_seed(s.seed, "detect-synth")) {}

  formats::PointCloud build() {
    ground();
    for (const auto& v : s_.vehicles) vehicle(v);
    for (const auto& t : s_.trees) tree(t);
    for (const auto& b : s_.bushes) blob(b.x, b.y, b.radius, b.base, b.top, formats::kLabelFoliage, false);
    for (const auto& b : s_.boulders) boulder(b);
    formats::PointCloud c;
    c.resize(pts_.size());
    const formats::FieldType ft = s_.float64 ? formats::kFloat64 : formats::kFloat32;
    auto& x = c.add("x", ft);
    auto& y = c.add("y", ft);
    auto& z = c.add("z", ft);
    auto& sx = c.add("sensor_x");
    auto& sy = c.add("sensor_y");
    auto& sz = c.add("sensor_z");
    auto& label = c.add("label", formats::kUint32);
    auto& inst = c.add("instance", formats::kUint32);
    for (std::size_t i = 0; i < pts_.size(); ++i) {
      Eigen::Vector3d p = pts_[i];
      if (s_.noise > 0) p += s_.noise * Eigen::Vector3d(rng_.normal(), rng_.normal(), rng_.normal());
      p += s_.offset;
      x[i] = p.x();
      y[i] = p.y();
      z[i] = p.z();
      sx[i] = 0;
      sy[i] = 0;
      sz[i] = 1;
      label[i] = labels_[i];
      inst[i] = inst_[i];
    }
    return c;
  }

 private:
  void add(const Eigen::Vector3d& p, std::uint32_t label, std::uint32_t inst) {
    if (std::abs(p.x()) > s_.half_extent || std::abs(p.y()) > s_.half_extent) return;
    pts_.push_back(p);
    labels_.push_back(label);
    inst_.push_back(inst);
  }
  bool hidden(double x, double y, double z) {
    // Occluded by a crown above the point.
    for (const auto& t : s_.trees) {
      if (std::hypot(x - t.x, y - t.y) < t.crown_radius && z < ground_z(s_, t.x, t.y) + t.crown_base) {
        return rng_.uniform() < s_.occlusion;
      }
    }
    return false;
  }
  void ground() {
    const double h = s_.half_extent, d = s_.spacing;
    const int n = int(std::floor(2 * h / d));
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const double x = -h + (i + rng_.uniform(-0.4, 0.4)) * d, y = -h + (j + rng_.uniform(-0.4, 0.4)) * d;
        bool covered = false;
        for (const auto& v : s_.vehicles) covered = covered || in_footprint(v, x, y);
        for (const auto& b : s_.boulders) covered = covered || std::hypot(x - b.x, y - b.y) < b.radius;
        if (covered) continue;
        const double z = ground_z(s_, x, y);
        if (hidden(x, y, z)) continue;
        add({x, y, z}, formats::kLabelGround, 0);
      }
  }
  void vehicle(const VehicleSpec& v) {
    const Eigen::Matrix3d R = vehicle_rotation(s_, v);
    const Eigen::Vector3d c(v.x, v.y, ground_z(s_, v.x, v.y));
    const double d = s_.spacing;
    // (nu, nw): outward normal of a side face in the vehicle frame (0, 0 on tops). A side
    // facing another vehicle closer than 0.5 m is not seen from the air.
    auto put = [&](double u, double w, double z, double nu = 0, double nw = 0) {
      const Eigen::Vector3d p = c + R * Eigen::Vector3d(u, w, z);
      if (nu != 0 || nw != 0) {
        const Eigen::Vector3d q = p + 0.5 * (R * Eigen::Vector3d(nu, nw, 0));
        for (const auto& o : s_.vehicles) {
          if (o.instance != v.instance && in_footprint(o, q.x(), q.y())) return;
        }
      }
      if (!hidden(p.x(), p.y(), p.z())) add(p, formats::kLabelTarget, v.instance);
    };
    if (!v.cabin) {
      box(put, 0, v.length, v.width, 0, v.height, true);
      return;
    }
    const double hb = 0.55 * v.height;
    box(put, 0, v.length, v.width, 0, hb, false);
    // The body's top outside the cabin.
    const double lc = 0.6 * v.length, wc = 0.75 * v.width, uc = -0.05 * v.length;
    const int nl = std::max(1, int(v.length / d)), nw = std::max(1, int(v.width / d));
    for (int a = 0; a < nl; ++a)
      for (int b = 0; b < nw; ++b) {
        const double u = -v.length / 2 + (a + rng_.uniform()) * v.length / nl,
                     w = -v.width / 2 + (b + rng_.uniform()) * v.width / nw;
        if (std::abs(u - uc) > lc / 2 || std::abs(w) > wc / 2) put(u, w, hb);
      }
    box(put, uc, lc, wc, hb, v.height, true);
  }
  // Box [uc -+ l/2] x [-+ w/2] x [z0, z1]: four sides, and the top when `top`.
  template <typename Put>
  void box(Put& put, double uc, double l, double w, double z0, double z1, bool top) {
    const double d = s_.spacing, h = z1 - z0;
    const int nl = std::max(1, int(l / d)), nw = std::max(1, int(w / d)), nh = std::max(1, int(h / d));
    if (top) {
      for (int a = 0; a < nl; ++a)
        for (int b = 0; b < nw; ++b)
          put(uc - l / 2 + (a + rng_.uniform()) * l / nl, -w / 2 + (b + rng_.uniform()) * w / nw, z1);
    }
    for (int a = 0; a < nl; ++a)
      for (int k = 0; k < nh; ++k) {
        const double u = uc - l / 2 + (a + rng_.uniform()) * l / nl, z = z0 + (k + rng_.uniform()) * h / nh;
        put(u, -w / 2, z, 0, -1);
        put(u, w / 2, z, 0, 1);
      }
    for (int b = 0; b < nw; ++b)
      for (int k = 0; k < nh; ++k) {
        const double ww = -w / 2 + (b + rng_.uniform()) * w / nw, z = z0 + (k + rng_.uniform()) * h / nh;
        put(uc - l / 2, ww, z, -1, 0);
        put(uc + l / 2, ww, z, 1, 0);
      }
  }
  // A crown or bush: points on an ellipsoid shell (depth 0.7-1.0 of the radius), between
  // base and top above the ground at (x, y).
  void blob(double x, double y, double r, double base, double top, std::uint32_t label, bool) {
    const double g = ground_z(s_, x, y), cz = g + 0.5 * (base + top), rz = 0.5 * (top - base);
    const double area = 4 * M_PI * std::pow((r * r * 2 + rz * r) / 3, 1.0);  // ~ ellipsoid area
    const int n = int(area / (s_.spacing * s_.spacing) * 0.5);
    for (int k = 0; k < n; ++k) {
      Eigen::Vector3d d(rng_.normal(), rng_.normal(), rng_.normal());
      if (d.norm() == 0) continue;
      d.normalize();
      const double depth = rng_.uniform(0.7, 1.0);
      add({x + d.x() * r * depth, y + d.y() * r * depth, cz + d.z() * rz * depth}, label, 0);
    }
  }
  void tree(const TreeSpec& t) {
    const double g = ground_z(s_, t.x, t.y);
    const int nz = int(t.crown_base / s_.spacing),
              na = std::max(4, int(2 * M_PI * t.trunk_radius / s_.spacing));
    for (int k = 0; k < nz; ++k)
      for (int a = 0; a < na; ++a) {
        const double phi = (a + rng_.uniform()) * 2 * M_PI / na;
        add({t.x + t.trunk_radius * std::cos(phi), t.y + t.trunk_radius * std::sin(phi),
             g + (k + rng_.uniform()) * s_.spacing},
            formats::kLabelFoliage, 0);
      }
    blob(t.x, t.y, t.crown_radius, t.crown_base, t.crown_top, formats::kLabelFoliage, true);
  }
  void boulder(const BoulderSpec& b) {
    const double g = ground_z(s_, b.x, b.y);
    const int n = int(2 * M_PI * b.radius * b.radius / (s_.spacing * s_.spacing));
    for (int k = 0; k < n; ++k) {
      Eigen::Vector3d d(rng_.normal(), rng_.normal(), std::abs(rng_.normal()));
      if (d.norm() == 0) continue;
      d.normalize();
      add({b.x + b.radius * d.x(), b.y + b.radius * d.y(), g + b.radius * d.z()}, 4, 0);
    }
  }

  const TileSpec& s_;
  common::Rng rng_;
  std::vector<Eigen::Vector3d> pts_;
  std::vector<std::uint32_t> labels_, inst_;
};

inline formats::PointCloud make_tile(const TileSpec& s) { return TileBuilder(s).build(); }

}  // namespace canopy::detect_test
