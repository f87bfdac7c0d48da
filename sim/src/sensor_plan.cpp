// Sensor-mode flight plan (tile.h plan_sensor; docs/decisions/sensor.md): flight lines from
// the swath and sidelap, pulses along the scan pattern, and one orthographic image per (line,
// scan-direction bin). No POV-Ray, terrain model or file here, so that the recipe reader (and
// its fuzzer) can check a sensor tile's size.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <tuple>

#include "canopy/common/error.h"
#include "canopy/common/geometry.h"
#include "canopy/common/math.h"
#include "canopy/sim/tile.h"

namespace canopy::sim {

using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

constexpr double kMaxFired = 5e7;   // pulses fired along all lines (the planning loop's work)
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

SensorPlan plan_sensor(const TileRecipe& r, const std::function<double(double, double)>& terrain,
                       double ground_lo, double top, const std::string& name) {
  SensorPlan plan;
  plan.sensor = *r.sensor;
  const Sensor& s = plan.sensor;
  const double zlo = ground_lo - 1, zhi = top + 1;
  plan.spacing = std::max(0.005, 2 * footprint_radius(s, s.altitude) / s.footprint_samples);
  const double half_swath = s.altitude * std::tan(s.scan_angle);
  const double line_spacing = 2 * half_swath * (1 - s.sidelap);
  double phi_far = 0;
  for (int b = 0; b < s.beams; ++b) phi_far = std::max(phi_far, std::abs(beam_angle(s, b)));
  // Where a beam meets the ground ahead of the sensor: h tan(phi) for heights h between the
  // sensor and the ground (any ground point lies between ground_lo and top), over the beams.
  double ahead_lo = 1e300, ahead_hi = -1e300;
  for (int b = 0; b < s.beams; ++b) {
    for (double h : {s.altitude - top - 1, s.altitude - ground_lo + 1}) {
      ahead_lo = std::min(ahead_lo, h * std::tan(beam_angle(s, b)));
      ahead_hi = std::max(ahead_hi, h * std::tan(beam_angle(s, b)));
    }
  }
  const double along_margin = 3 * footprint_radius(s, s.altitude / std::cos(phi_far)) + 1;
  // Rejecting a pulse before finding its ground point: its axis meets z = 0 within this much
  // of where it meets the terrain (heights within [ground_lo, top]).
  const double reach = std::max(std::abs(ground_lo), std::abs(top)) + 1;
  const double phi_lo = beam_angle(s, 0);
  const Vector2d corners[4] = {{0, 0}, {r.extent_x, 0}, {r.extent_x, r.extent_y}, {0, r.extent_y}};
  auto height_at = [&](double x, double y) { return terrain ? terrain(x, y) : 0.0; };

  std::map<std::tuple<int, int, int>, Bin> bins;
  double clock = 0;
  for (double heading : r.headings) {
    const Vector2d f0(std::cos(heading), std::sin(heading)), c(-f0.y(), f0.x());
    const common::Extent2 e = common::extent_along(corners, f0, c);
    const double cc = (e.vmin + e.vmax) / 2, hw = (e.vmax - e.vmin) / 2;
    const int kmax = static_cast<int>(std::floor((hw + half_swath + std::abs(r.swath_offset)) / line_spacing));
    for (int k = -kmax; k <= kmax; ++k) {
      const double offset = k * line_spacing + r.swath_offset;
      if (std::abs(offset) - half_swath >= hw) continue;
      FlightLine line;
      line.id = static_cast<int>(plan.lines.size()) + 1;
      const bool back = (line.id % 2) == 0;  // lines flown back and forth
      const Vector2d f = back ? Vector2d(-f0) : f0;
      line.heading = std::atan2(f.y(), f.x());
      line.offset = offset;
      // The sensor's positions (along f0) from which a beam reaches the tile.
      const double lo = back ? e.umin - along_margin + ahead_lo : e.umin - along_margin - ahead_hi;
      const double hi = back ? e.umax + along_margin + ahead_hi : e.umax + along_margin - ahead_lo;
      const double a_start = back ? hi : lo;
      const double length = hi - lo;
      const Vector2d start2 = a_start * f0 + (cc + offset) * c;
      line.start = Vector3d(start2.x(), start2.y(), s.altitude);
      line.end = line.start + length * Vector3d(f.x(), f.y(), 0);
      line.t0 = clock;
      line.t1 = clock + length / s.speed;
      const double n = std::floor(length / s.speed * s.pulse_rate);
      plan.fired += n;
      if (plan.fired > kMaxFired) {
        throw common::DataError(name,
                                "the sensor would fire more than 5e7 pulses over the tile's flight lines "
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
        {  // cheap rejection: the axis at z = 0, with the most the terrain and footprint can move it
          const Vector3d g0 = sensor + (sensor.z() / -d.z()) * d;
          const double slack = reach * std::sqrt(1 - d.z() * d.z()) / -d.z() +
                               2 * footprint_radius(s, (sensor.z() - ground_lo) / -d.z()) + 1;
          if (g0.x() < -slack || g0.y() < -slack || g0.x() > r.extent_x + slack || g0.y() > r.extent_y + slack)
            continue;
        }
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

}  // namespace canopy::sim
