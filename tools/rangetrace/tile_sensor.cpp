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

constexpr double kMaxFired = 2e8;   // pulses fired along all lines (the planning loop's work)
constexpr double kMaxPulses = 5e6;  // pulses aimed into the tile (memory: ~0.2 kB each)
constexpr std::size_t kMaxSensorViews = 20000;

// The pulses of one image while planning: its line's direction and the spread of its angles.
struct Bin {
  Vector2d f = Vector2d::UnitX();
  double theta_lo = 1e9, theta_hi = -1e9, phi_lo = 1e9, phi_hi = -1e9, radius = 0;
  std::vector<std::size_t> pulses;
  int line = 0;
};

// The image of a bin: orthographic along the bin's mean direction, covering every pulse's axis
// point on the ground plus its footprint, with depth coded from above `zhi` to below `zlo`.
TileView bin_view(const Bin& b, const std::vector<Pulse>& pulses, double phi_mid, double spacing, double zlo,
                  double zhi) {
  const double theta = (b.theta_lo + b.theta_hi) / 2;
  TileView v;
  v.toward = -beam_direction(b.f, theta, phi_mid);
  const Vector3d f3(b.f.x(), b.f.y(), 0);
  v.right = f3.cross(v.toward).normalized();
  v.up = v.toward.cross(v.right).normalized();
  v.spacing = spacing;
  double u0 = 1e300, u1 = -1e300, w0 = 1e300, w1 = -1e300;
  for (std::size_t p : b.pulses) {
    const Vector3d& g = pulses[p].ground;
    u0 = std::min(u0, g.dot(v.right));
    u1 = std::max(u1, g.dot(v.right));
    w0 = std::min(w0, g.dot(v.up));
    w1 = std::max(w1, g.dot(v.up));
  }
  const double margin = b.radius + 2 * spacing;
  u0 -= margin, u1 += margin, w0 -= margin, w1 += margin;
  // Along the ray through image point (u, w): X = u right + w up + lambda toward, so a hit at
  // height z has lambda = (z - u right.z - w up.z) / toward.z.
  double lmax = -1e300, lmin = 1e300;
  for (double u : {u0, u1}) {
    for (double w : {w0, w1}) {
      lmax = std::max(lmax, (zhi - u * v.right.z() - w * v.up.z()) / v.toward.z());
      lmin = std::min(lmin, (zlo - u * v.right.z() - w * v.up.z()) / v.toward.z());
    }
  }
  const double plane = lmax + 1;  // the image plane, 1 m above the highest possible hit
  v.pixels_x = std::max(1.0, std::ceil((u1 - u0) / spacing));
  v.pixels_y = std::max(1.0, std::ceil((w1 - w0) / spacing));
  v.width = static_cast<int>(std::min(v.pixels_x, kMaxImageSide));
  v.height = static_cast<int>(std::min(v.pixels_y, kMaxImageSide));
  v.origin = (u0 + u1) / 2 * v.right + (w0 + w1) / 2 * v.up + plane * v.toward;
  v.depth_lo = 0.5;
  v.depth_span = lmax - lmin + 1;
  v.line = b.line;
  return v;
}

}  // namespace

SensorPlan plan_sensor(const TileRecipe& r, const TerrainModel* terrain, double ground_lo, double top,
                       const std::string& name) {
  SensorPlan plan;
  plan.sensor = *r.sensor;
  const Sensor& s = plan.sensor;
  const double zlo = ground_lo - 1, zhi = top + 1;
  plan.spacing = std::max(0.005, 2 * footprint_radius(s, s.altitude) / s.footprint_samples);
  const double half_swath = s.altitude * std::tan(s.scan_angle);
  const double line_spacing = 2 * half_swath * (1 - s.sidelap);
  double phi_far = 0;
  for (int b = 0; b < s.beams; ++b) phi_far = std::max(phi_far, std::abs(beam_angle(s, b)));
  const double along_margin = (s.altitude + top - ground_lo) * std::tan(phi_far) +
                              3 * footprint_radius(s, s.altitude / std::cos(phi_far)) + 1;
  const double phi_lo = beam_angle(s, 0);
  const Vector2d corners[4] = {{0, 0}, {r.extent_x, 0}, {r.extent_x, r.extent_y}, {0, r.extent_y}};
  auto height_at = [&](double x, double y) { return terrain ? terrain->height(x, y) : 0.0; };

  std::map<std::tuple<int, int, int>, Bin> bins;
  double clock = 0;
  for (double heading : r.headings) {
    const Vector2d f0(std::cos(heading), std::sin(heading)), c(-f0.y(), f0.x());
    const common::Extent2 e = common::extent_along(corners, f0, c);
    const double cc = (e.vmin + e.vmax) / 2, hw = (e.vmax - e.vmin) / 2;
    const int kmax = static_cast<int>(std::floor((hw + half_swath) / line_spacing));
    for (int k = -kmax; k <= kmax; ++k) {
      const double offset = k * line_spacing;
      if (std::abs(offset) - half_swath >= hw) continue;
      FlightLine line;
      line.id = static_cast<int>(plan.lines.size()) + 1;
      const bool back = (line.id % 2) == 0;  // lines flown back and forth
      const Vector2d f = back ? Vector2d(-f0) : f0;
      line.heading = std::atan2(f.y(), f.x());
      line.offset = offset;
      const double a_start = back ? e.umax + along_margin : e.umin - along_margin;
      const double length = e.umax - e.umin + 2 * along_margin;
      const Vector2d start2 = a_start * f0 + (cc + offset) * c;
      line.start = Vector3d(start2.x(), start2.y(), s.altitude);
      line.end = line.start + length * Vector3d(f.x(), f.y(), 0);
      line.t0 = clock;
      line.t1 = clock + length / s.speed;
      const double n = std::floor(length / s.speed * s.pulse_rate);
      plan.fired += n;
      if (plan.fired > kMaxFired) {
        throw common::DataError(name,
                                "the sensor would fire more than 2e8 pulses over the tile's flight lines "
                                "(lower sensor.pulse_rate or raise sensor.speed)");
      }
      for (double q = 0; q < n; ++q) {
        const double t = line.t0 + q / s.pulse_rate;
        const auto [theta, rising] = scan_angle_at(s, t);
        if (std::abs(theta) > s.scan_angle) continue;  // a rotating head looking up or sideways
        const int beam = static_cast<int>(std::fmod(q, s.beams));
        const double phi = beam_angle(s, beam);
        const Vector3d d = beam_direction(f, theta, phi);
        const Vector3d sensor = line.start + (t - line.t0) * s.speed * Vector3d(f.x(), f.y(), 0);
        double zr = height_at(sensor.x(), sensor.y()), range = 0;
        Vector3d g;
        for (int it = 0; it < 4; ++it) {  // where the axis meets the terrain (fixed point)
          range = (sensor.z() - zr) / -d.z();
          g = sensor + range * d;
          zr = height_at(std::clamp(g.x(), 0.0, r.extent_x), std::clamp(g.y(), 0.0, r.extent_y));
        }
        const double rad = footprint_radius(s, range);
        if (g.x() < -rad || g.y() < -rad || g.x() > r.extent_x + rad || g.y() > r.extent_y + rad) continue;
        if (plan.pulses.size() >= kMaxPulses) {
          throw common::DataError(name,
                                  "more than 5e6 pulses fall in the tile (lower the sensor's pulse rate)");
        }
        Pulse p;
        p.time = t;
        p.sensor = sensor;
        p.dir = d;
        p.ground = g;
        p.scan_angle = theta;
        p.scan_dir = rising;
        p.line = line.id;
        const int it = static_cast<int>(std::floor((theta + s.scan_angle) / s.angle_step));
        const int ip = static_cast<int>(std::floor((phi - phi_lo) / s.angle_step + 1e-9));
        Bin& b = bins[{line.id, it, ip}];
        b.f = f;
        b.line = line.id;
        b.theta_lo = std::min(b.theta_lo, theta);
        b.theta_hi = std::max(b.theta_hi, theta);
        b.phi_lo = std::min(b.phi_lo, phi);
        b.phi_hi = std::max(b.phi_hi, phi);
        b.radius = std::max(b.radius, rad);
        b.pulses.push_back(plan.pulses.size());
        plan.pulses.push_back(p);
      }
      plan.lines.push_back(line);
      clock = line.t1 + s.line_turn;
    }
  }
  if (bins.size() > kMaxSensorViews) {
    throw common::DataError(name, "the sensor's scan needs " + std::to_string(bins.size()) +
                                      " images (at most 20000): raise sensor.angle_step");
  }
  for (auto& [key, b] : bins) {
    const int view = static_cast<int>(plan.views.size());
    plan.views.push_back(bin_view(b, plan.pulses, (b.phi_lo + b.phi_hi) / 2, plan.spacing, zlo, zhi));
    for (std::size_t p : b.pulses) plan.pulses[p].view = view;
  }
  return plan;
}

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

std::vector<SubHit> sample_pulse(const Sensor& s, const Pulse& pulse, const TileView& v, const Image16& img) {
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
    hits.push_back({range + depth - depth_ground, weight, cls, inst});
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
  for (std::size_t k = 0; k < plan.views.size(); ++k) {
    if (of_view[k].empty()) continue;
    const Image16 img = image(static_cast<int>(k));
    for (std::size_t p : of_view[k]) {
      returns[p] = detect_returns(s, sample_pulse(s, plan.pulses[p], plan.views[k], img), photon_seed + p);
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
