#include "canopy/formats/sensor_direction.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>

#include "canopy/common/error.h"
#include "canopy/common/math.h"
#include "canopy/formats/cloud_eigen.h"

namespace canopy::formats {

namespace {

const std::vector<double>& column(const PointCloud& cloud, const char* field, const std::string& name,
                                  const char* why) {
  cloud.require({field}, name, why);
  const std::vector<double>& c = cloud.col(field);
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!std::isfinite(c[i])) {
      throw common::DataError(name, "point " + std::to_string(i) + " has a non-finite " + field);
    }
  }
  return c;
}

std::vector<Eigen::Vector3d> world_points(const PointCloud& cloud, const SensorDirectionOptions& o,
                                          const std::string& name) {
  std::vector<Eigen::Vector3d> p = finite_vectors(cloud, name);
  for (auto& q : p) q = o.to_world * q;
  return p;
}

}  // namespace

SensorSource parse_sensor_source(const std::string& text, const std::string& option) {
  if (text == "auto") return SensorSource::kAuto;
  if (text == "columns") return SensorSource::kColumns;
  if (text == "trajectory") return SensorSource::kTrajectory;
  if (text == "scan-angle") return SensorSource::kScanAngle;
  if (text == "vertical") return SensorSource::kVertical;
  throw common::UsageError(option + ": '" + text +
                           "' is not one of auto, columns, trajectory, scan-angle, vertical");
}

const char* sensor_source_name(SensorSource s) {
  switch (s) {
    case SensorSource::kAuto: return "auto";
    case SensorSource::kColumns: return "columns";
    case SensorSource::kTrajectory: return "trajectory";
    case SensorSource::kScanAngle: return "scan-angle";
    case SensorSource::kVertical: return "vertical";
  }
  return "?";
}

bool flight_direction(const std::vector<Eigen::Vector3d>& world, const std::vector<double>& gps_time,
                      const std::vector<double>& scan_angle, const std::vector<std::size_t>& rows,
                      Eigen::Vector2d* direction, double* across_gain) {
  if (rows.size() < 2) return false;
  double t0 = 0, a0 = 0;
  Eigen::Vector2d p0 = Eigen::Vector2d::Zero();
  for (std::size_t i : rows) {
    t0 += gps_time[i];
    a0 += scan_angle[i];
    p0 += world[i].head<2>();
  }
  const double n = static_cast<double>(rows.size());
  t0 /= n;
  a0 /= n;
  p0 /= n;
  // Normal equations of p - p0 = v (t - t0) + b (a - a0), both coordinates at once.
  double stt = 0, sta = 0, saa = 0;
  Eigen::Vector2d spt = Eigen::Vector2d::Zero(), spa = Eigen::Vector2d::Zero();
  for (std::size_t i : rows) {
    const double t = gps_time[i] - t0, a = scan_angle[i] - a0;
    const Eigen::Vector2d p = world[i].head<2>() - p0;
    stt += t * t;
    sta += t * a;
    saa += a * a;
    spt += p * t;
    spa += p * a;
  }
  if (!(stt > 0)) return false;
  Eigen::Vector2d v, b = Eigen::Vector2d::Zero();
  const double det = stt * saa - sta * sta;
  // The scan angle joins the fit only when it varies independently of time (a fixed-angle look,
  // as the simulator's orthographic images, leaves it out: b would be undetermined).
  if (saa > 0 && det > 1e-9 * stt * saa) {
    v = (spt * saa - spa * sta) / det;
    b = (spa * stt - spt * sta) / det;
  } else {
    v = spt / stt;
  }
  const double speed = v.norm();
  if (!(speed > 0) || !std::isfinite(speed)) return false;
  *direction = v / speed;
  if (across_gain != nullptr) {
    const Eigen::Vector2d right(direction->y(), -direction->x());
    *across_gain = b.dot(right);
  }
  return true;
}

SensorDirections sensor_directions(const PointCloud& points, const SensorDirectionOptions& o,
                                   const std::string& name) {
  SensorDirections r;
  SensorSource s = o.source;
  if (s == SensorSource::kAuto) {
    if (has_fields(points, kSensorFields)) {
      s = SensorSource::kColumns;
    } else if (o.trajectory != nullptr) {
      s = SensorSource::kTrajectory;
    } else if (points.has("scan_angle") && points.has("gps_time")) {
      s = SensorSource::kScanAngle;
    } else {
      s = SensorSource::kVertical;
      r.warnings.push_back(name +
                           ": no sensor_x/y/z, no --trajectory, no scan_angle + gps_time: the free-space "
                           "test assumes every point was seen from straight above (vertical)");
    }
  }
  r.used = s;
  const Eigen::Matrix3d to_local = o.to_world.linear().transpose();
  const Eigen::Vector3d up_local = to_local * Eigen::Vector3d::UnitZ();
  switch (s) {
    case SensorSource::kAuto: break;
    case SensorSource::kColumns:
      points.require({"sensor_x", "sensor_y", "sensor_z"}, name, "--sensor-direction columns");
      r.summary = "sensor directions from the sensor_x/y/z columns";
      return r;
    case SensorSource::kVertical:
      r.directions.assign(points.size(), up_local);
      r.summary = "sensor directions: the vertical";
      return r;
    case SensorSource::kTrajectory: {
      if (o.trajectory == nullptr)
        throw common::UsageError("--sensor-direction trajectory needs --trajectory FILE");
      const auto& t =
          column(points, "gps_time", name, "the trajectory gives the sensor at each point's GPS time");
      const auto world = world_points(points, o, name);
      r.directions.resize(world.size());
      double lo = 0, hi = 0;
      for (std::size_t i = 0; i < world.size(); ++i) {
        const auto sp = trajectory_position(*o.trajectory, t[i], o.tolerance, o.trajectory_name);
        const Eigen::Vector3d d = Eigen::Vector3d(sp[0], sp[1], sp[2]) - world[i];
        const double len = d.norm();
        if (!(len > 1e-9)) {
          throw common::DataError(name, "point " + std::to_string(i) + " lies on the trajectory (" +
                                            o.trajectory_name + "): no direction toward the sensor");
        }
        r.directions[i] = to_local * (d / len);
        const double off = std::acos(std::clamp(d.z() / len, -1.0, 1.0)) * 180 / common::kPi;
        lo = i == 0 ? off : std::min(lo, off);
        hi = i == 0 ? off : std::max(hi, off);
      }
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "sensor directions from the trajectory %s (%.1f to %.1f deg off vertical)",
                    o.trajectory_name.c_str(), lo, hi);
      r.summary = buf;
      return r;
    }
    case SensorSource::kScanAngle: {
      const auto& t =
          column(points, "gps_time", name, "the flight direction comes from the points' GPS times");
      const auto& a = column(points, "scan_angle", name, "--sensor-direction scan-angle");
      const auto world = world_points(points, o, name);
      // Flight lines, then segments of each line separated by GPS time gaps.
      std::map<double, std::vector<std::size_t>> lines;
      const bool has_source = points.has("point_source_id");
      for (std::size_t i = 0; i < world.size(); ++i) {
        lines[has_source ? points.col("point_source_id")[i] : 0.0].push_back(i);
      }
      r.directions.resize(world.size());
      int segments = 0, failed = 0, reversed = 0;
      std::string headings;
      for (auto& [id, rows] : lines) {
        std::stable_sort(rows.begin(), rows.end(), [&](std::size_t x, std::size_t y) { return t[x] < t[y]; });
        std::size_t b = 0;
        while (b < rows.size()) {
          std::size_t e = b + 1;
          while (e < rows.size() && t[rows[e]] - t[rows[e - 1]] <= kFlightSegmentGap) ++e;
          const std::vector<std::size_t> seg(rows.begin() + static_cast<std::ptrdiff_t>(b),
                                             rows.begin() + static_cast<std::ptrdiff_t>(e));
          ++segments;
          Eigen::Vector2d f;
          double gain = 0;
          if (flight_direction(world, t, a, seg, &f, &gain)) {
            const Eigen::Vector3d right(f.y(), -f.x(), 0);
            if (gain < 0) ++reversed;
            for (std::size_t i : seg) {
              const double th = a[i] * common::kPi / 180;
              r.directions[i] = to_local * (std::cos(th) * Eigen::Vector3d::UnitZ() - std::sin(th) * right);
            }
            char buf[48];
            std::snprintf(buf, sizeof buf, "%s%.0f", headings.empty() ? "" : " ",
                          std::atan2(f.y(), f.x()) * 180 / common::kPi);
            if (headings.size() < 120) headings += buf;
          } else {
            ++failed;
            for (std::size_t i : seg) r.directions[i] = up_local;
          }
          b = e;
        }
      }
      if (failed > 0) {
        r.warnings.push_back(name + ": " + std::to_string(failed) + " of " + std::to_string(segments) +
                             " flight segments have GPS times that do not give a flight direction: their "
                             "points get the vertical");
      }
      if (reversed > 0) {
        r.warnings.push_back(name + ": in " + std::to_string(reversed) + " of " + std::to_string(segments) +
                             " flight segments the points move left as the scan angle grows (LAS puts "
                             "positive angles to the right of the flight): check the file's scan angle sign");
      }
      r.summary = "sensor directions from scan angle + flight direction (" + std::to_string(segments) +
                  " flight segments, headings " + (headings.empty() ? std::string("none") : headings) +
                  " deg from +x)";
      return r;
    }
  }
  return r;
}

}  // namespace canopy::formats
