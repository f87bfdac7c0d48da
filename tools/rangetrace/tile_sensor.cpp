// Sensor-mode tiles (issue 28; docs/decisions/sensor.md): flight lines planned from the sensor,
// pulses along the scan pattern, one orthographic image per (line, scan-direction bin), and the
// pulses' sub-rays sampled from those images into waveforms and discrete returns.
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "canopy/common/error.h"
#include "canopy/common/geometry.h"
#include "canopy/common/math.h"
#include "canopy/common/rng.h"
#include "canopy/formats/labels.h"
#include "rangetrace/tile.h"
#include "rangetrace/tile_sensor.h"

namespace canopy::rangetrace {

using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

// ASPRS class of a return: 2 ground; vegetation 3 / 4 / 5 below 0.5 m / 2 m / above over the
// terrain; 6 sheds (buildings); 1 vehicles and other clutter (as producers leave them).
int asprs(const Tile& tile, const TerrainModel& terrain, const Vector3d& p, std::uint32_t cls, int instance) {
  switch (static_cast<Class>(cls)) {
    case Class::kGround: return 2;
    case Class::kVegetation: {
      const double h = p.z() - terrain.height(std::clamp(p.x(), 0.0, tile.recipe.extent_x),
                                              std::clamp(p.y(), 0.0, tile.recipe.extent_y));
      return h < 0.5 ? 3 : h < 2 ? 4 : 5;
    }
    case Class::kClutter: {
      const auto k = static_cast<std::size_t>(instance - 1);
      return k < tile.objects.size() && tile.objects[k].kind == "shed" ? 6 : 1;
    }
    default: return 1;
  }
}

std::uint32_t canopy_label(std::uint32_t cls) {
  switch (static_cast<Class>(cls)) {
    case Class::kGround: return formats::kLabelGround;
    case Class::kVegetation: return formats::kLabelFoliage;
    case Class::kClutter: return formats::kLabelClutter;
    default: return formats::kLabelTarget;
  }
}

}  // namespace

SurfaceReflectance tile_surfaces(const Sensor& s, const Tile& tile, std::uint64_t seed) {
  struct Car {
    double paint = 1;
    bool glass = false;
    Eigen::Affine3d to_model = Eigen::Affine3d::Identity();  // tile -> the model's own frame
    double z0 = 0, z1 = 1;                                   // glass band (model z)
  };
  std::map<std::int32_t, Car> cars;
  for (const auto& v : tile.vehicles) {
    Car c;
    c.paint = paint_reflectance(s, seed, v.instance);
    const auto& lo = tile.model_bounds[v.model_index].first;
    const auto& hi = tile.model_bounds[v.model_index].second;
    const Vector3d anchor((lo.x() + hi.x()) / 2, (lo.y() + hi.y()) / 2, lo.z());
    // As rendered (tile_render.cpp pov_objects): tile point = pose * (model point - anchor).
    c.to_model = (v.pose.transform() * Eigen::Translation3d(-anchor)).inverse();
    c.glass = model_has_glass(v.model_name);
    c.z0 = lo.z() + kGlassLo * (hi.z() - lo.z());
    c.z1 = lo.z() + kGlassHi * (hi.z() - lo.z());
    cars[v.instance] = c;
  }
  return [s, cars](const Vector3d& p, std::uint32_t cls, std::int32_t instance) {
    switch (static_cast<Class>(cls)) {
      case Class::kGround: return reflectance(s, Surface::kGround, 0);
      case Class::kVegetation: return reflectance(s, Surface::kVegetation, 0);
      case Class::kClutter: return reflectance(s, Surface::kClutter, 0);
      default: break;
    }
    const auto it = cars.find(instance);
    if (it == cars.end()) return reflectance(s, Surface::kPaint, s.paint_max);
    const Car& c = it->second;
    if (c.glass) {
      const double z = (c.to_model * p).z();
      if (z >= c.z0 && z < c.z1) return reflectance(s, Surface::kGlass, c.paint);
    }
    return reflectance(s, Surface::kPaint, c.paint);
  };
}

std::vector<SubHit> sample_pulse(const Sensor& s, const Pulse& pulse, const TileView& v, const Image16& img,
                                 const SurfaceReflectance& reflect) {
  const double range = (pulse.ground - pulse.sensor).norm();
  const double rad = footprint_radius(s, range);
  const Vector3d q = pulse.ground - v.origin;
  const double uc = q.dot(v.right) / v.spacing + v.width / 2.0 - 0.5;
  const double wc = v.height / 2.0 - 0.5 - q.dot(v.up) / v.spacing;
  const double depth_ground = -q.dot(v.toward);  // depth of the axis point below the image plane
  const double rp = rad / v.spacing;
  std::vector<SubHit> hits;
  double total = 0;
  auto take = [&](int i, int j, double weight) {
    total += weight;
    if (i < 0 || j < 0 || i >= img.width || j >= img.height) return;
    double depth = 0;
    std::uint32_t cls = 0;
    std::int32_t inst = 0;
    if (!decode_pixel(img, v, i, j, &depth, &cls, &inst)) return;
    double rho = 1;
    if (reflect) {
      const double x = (i + 0.5) / v.width - 0.5, y = 0.5 - (j + 0.5) / v.height;
      const Vector3d at =
          v.origin + x * v.width * v.spacing * v.right + y * v.height * v.spacing * v.up - depth * v.toward;
      rho = reflect(at, cls, inst);
    }
    // A surface that returns nothing still stops the sub-ray (the first hit is all the image has).
    if (rho > 0) hits.push_back({range + depth - depth_ground, weight * rho, cls, inst});
  };
  for (int j = static_cast<int>(std::ceil(wc - rp)); j <= static_cast<int>(std::floor(wc + rp)); ++j) {
    for (int i = static_cast<int>(std::ceil(uc - rp)); i <= static_cast<int>(std::floor(uc + rp)); ++i) {
      const double d2 = ((i - uc) * (i - uc) + (j - wc) * (j - wc)) / (rp * rp);
      if (d2 <= 1) take(i, j, std::exp(-2 * d2));  // Gaussian beam, 1/e^2 at the footprint's edge
    }
  }
  if (total == 0) take(static_cast<int>(std::lround(uc)), static_cast<int>(std::lround(wc)), 1);
  for (auto& h : hits) h.energy /= total;
  return hits;
}

void add_sensor_columns(formats::PointCloud* cloud) {
  using formats::FieldType;
  const std::pair<const char*, FieldType> cols[] = {{"x", formats::kFloat64},
                                                    {"y", formats::kFloat64},
                                                    {"z", formats::kFloat64},
                                                    {"intensity", {'U', 2}},
                                                    {"return_number", formats::kUint8},
                                                    {"number_of_returns", formats::kUint8},
                                                    {"scan_direction_flag", formats::kUint8},
                                                    {"classification", formats::kUint8},
                                                    {"scan_angle", formats::kFloat32},
                                                    {"point_source_id", {'U', 2}},
                                                    {"gps_time", formats::kFloat64},
                                                    {"label", formats::kUint32},
                                                    {"instance", formats::kInt32},
                                                    {"echo_width", formats::kFloat32}};
  for (const auto& [n, t] : cols) cloud->add(n, t);
}

TileScan sense_tile(const SensorPlan& plan, const std::function<Image16(int)>& image, Tile* tile,
                    std::uint64_t seed) {
  const Sensor& s = plan.sensor;
  const TileRecipe& r = tile->recipe;
  const TerrainModel terrain(r, tile->seed);
  std::vector<std::vector<Return>> returns(plan.pulses.size());
  std::vector<std::vector<std::size_t>> of_view(plan.views.size());
  for (std::size_t p = 0; p < plan.pulses.size(); ++p) of_view[plan.pulses[p].view].push_back(p);
  const std::uint64_t photon_seed = common::derive_seed(seed, "sensor-photons");
  const SurfaceReflectance surfaces = tile_surfaces(s, *tile, seed);
  for (std::size_t k = 0; k < plan.views.size(); ++k) {
    if (of_view[k].empty()) continue;
    const Image16 img = image(static_cast<int>(k));
    for (std::size_t p : of_view[k]) {
      returns[p] =
          detect_returns(s, sample_pulse(s, plan.pulses[p], plan.views[k], img, surfaces), photon_seed + p);
    }
  }
  TileScan scan;
  add_sensor_columns(&scan.cloud);
  const Vector3d origin = r.has_origin ? r.origin : Vector3d::Zero();
  common::Rng noise(common::derive_seed(seed, "sensor-range-noise"));
  std::size_t aimed = 0, with_return = 0;
  tile->pulses_by_returns.assign(s.max_returns + 1, 0);
  for (std::size_t p = 0; p < plan.pulses.size(); ++p) {
    const Pulse& pulse = plan.pulses[p];
    const bool in_tile = pulse.ground.x() >= 0 && pulse.ground.y() >= 0 && pulse.ground.x() <= r.extent_x &&
                         pulse.ground.y() <= r.extent_y;
    if (in_tile) ++aimed, ++tile->pulses_by_returns[returns[p].size()];
    for (std::size_t k = 0; k < returns[p].size(); ++k) {
      const Return& ret = returns[p][k];
      const double range = ret.range + s.range_noise * noise.normal();
      const Vector3d x = pulse.sensor + range * pulse.dir;
      if (x.x() < 0 || x.y() < 0 || x.x() > r.extent_x || x.y() > r.extent_y) continue;
      if (k == 0) ++with_return;
      const std::size_t row = scan.cloud.size();
      scan.cloud.resize(row + 1);
      for (int a = 0; a < 3; ++a) scan.cloud.col(a)[row] = x[a] + origin[a];
      scan.cloud.col(3)[row] = std::round(std::min(1.0, ret.amplitude) * 65535);
      scan.cloud.col(4)[row] = static_cast<double>(k + 1);
      scan.cloud.col(5)[row] = static_cast<double>(returns[p].size());
      scan.cloud.col(6)[row] = pulse.scan_dir ? 1 : 0;
      scan.cloud.col(7)[row] = asprs(*tile, terrain, x, ret.cls, ret.instance);
      scan.cloud.col(8)[row] = static_cast<float>(pulse.scan_angle * 180 / common::kPi);
      scan.cloud.col(9)[row] = pulse.line;
      scan.cloud.col(10)[row] = pulse.time;
      scan.cloud.col(11)[row] = canopy_label(ret.cls);
      scan.cloud.col(12)[row] = ret.cls == static_cast<std::uint32_t>(Class::kVehicle) ? ret.instance : 0;
      scan.cloud.col(13)[row] = static_cast<float>(ret.width);
    }
  }
  const double area = r.extent_x * r.extent_y;
  tile->flight_lines = plan.lines;
  tile->returns_per_m2 = scan.cloud.size() / area;
  tile->pulses_per_m2 = with_return / area;
  tile->fired_per_m2 = aimed / area;
  scan.points_per_view.push_back(scan.cloud.size());
  scan.area_per_view.push_back(area);
  return scan;
}

formats::Trajectory tile_trajectory(const Tile& tile) {
  formats::Trajectory traj;
  const TileRecipe& r = tile.recipe;
  const Vector3d origin = r.has_origin ? r.origin : Vector3d::Zero();
  traj.comments.push_back("rangetrace " + tile.name + ": " + std::to_string(tile.flight_lines.size()) +
                          " flight lines at 10 Hz; roll and pitch 0 (a stable platform)");
  for (const auto& l : tile.flight_lines) {
    const auto n = static_cast<int>(std::ceil((l.t1 - l.t0) * 10));
    for (int k = 0; k <= n; ++k) {
      const double a = static_cast<double>(k) / n;
      const Vector3d p = l.start + a * (l.end - l.start) + origin;
      traj.samples.push_back(
          {l.t0 + a * (l.t1 - l.t0), p.x(), p.y(), p.z(), 0.0, 0.0, l.heading * 180 / common::kPi + 0.0});
    }
  }
  return traj;
}

std::string trajectory_path(const std::string& scan) {
  const auto slash = scan.find_last_of('/');
  const auto dot = scan.find_last_of('.');
  const bool ext = dot != std::string::npos && (slash == std::string::npos || dot > slash + 1);
  return (ext ? scan.substr(0, dot) : scan) + ".traj";
}

}  // namespace canopy::rangetrace
