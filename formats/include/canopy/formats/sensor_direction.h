// The direction from each point toward the sensor that saw it (issue 26), from what a point
// file has: the simulator's sensor_x/y/z columns, or for real LAS a trajectory (sensor position
// at the point's GPS time), or scan angle + flight direction, or the vertical as the last
// resort. verify's free-space test needs one direction per point (docs/decisions/verify.md,
// "Sensor directions from what LAS has").
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"
#include "canopy/formats/trajectory.h"

namespace canopy::formats {

enum class SensorSource { kAuto, kColumns, kTrajectory, kScanAngle, kVertical };

// "auto" | "columns" | "trajectory" | "scan-angle" | "vertical"; common::UsageError naming
// `option` otherwise.
SensorSource parse_sensor_source(const std::string& text, const std::string& option);
const char* sensor_source_name(SensorSource s);

// A new flight segment starts where a flight line's points (same point_source_id) are more
// than this apart in GPS time (s): the same line's fore and aft looks, or a line flown twice.
inline constexpr double kFlightSegmentGap = 1.0;

struct SensorDirectionOptions {
  SensorSource source = SensorSource::kAuto;
  const Trajectory* trajectory = nullptr;  // needed by kTrajectory; kAuto uses it when given
  std::string trajectory_name;             // the trajectory file, for messages
  double tolerance = 1.0;                  // s, trajectory_position's tolerance at the ends
  // Points' frame -> the world frame (the trajectory's and the tile's; its z is the vertical),
  // e.g. a detect candidate's transform. Directions are returned in the points' frame.
  Eigen::Isometry3d to_world = Eigen::Isometry3d::Identity();
};

struct SensorDirections {
  SensorSource used = SensorSource::kColumns;  // never kAuto
  std::vector<Eigen::Vector3d> directions;     // unit, points' frame; empty for kColumns
  std::vector<std::string> warnings;           // the caller logs them (vertical fallback, ...)
  std::string summary;                         // one line: what was used
};

// Decides the source (kAuto: columns when the cloud has sensor_x/y/z, else the trajectory when
// given, else scan angle + flight direction when the cloud has scan_angle and gps_time, else the
// vertical with a warning) and computes the directions; for kColumns it computes nothing (the
// caller reads the columns as before). Throws common::DataError naming `name` (or the
// trajectory file) when the chosen source's columns are missing or a GPS time lies outside the
// trajectory, common::UsageError for kTrajectory without a trajectory.
//   trajectory:  normalize(S(gps_time) - p), S linear in time (formats/trajectory.h).
//   scan-angle:  the flight direction f of each flight segment (points of one point_source_id,
//                split at GPS time gaps > kFlightSegmentGap) is the velocity v of the least
//                squares fit  p_xy = p0 + v (t - t0) + b angle  over the segment (b absorbs the
//                sweep across the line); with r = f turned 90 deg clockwise (the right of the
//                flight, where LAS puts positive scan angles), the direction toward the sensor
//                is  cos(angle) z - sin(angle) r  (the scanner's pitch and the terrain are
//                ignored). A segment whose GPS times do not spread (< 2 distinct times) gets the
//                vertical, with a warning.
//   vertical:    the world z axis.
SensorDirections sensor_directions(const PointCloud& points, const SensorDirectionOptions& options,
                                   const std::string& name);

// The horizontal unit flight direction of points given in the world frame with GPS times and
// scan angles (degrees), by the fit above; false when the times do not determine it.
bool flight_direction(const std::vector<Eigen::Vector3d>& world, const std::vector<double>& gps_time,
                      const std::vector<double>& scan_angle, const std::vector<std::size_t>& rows,
                      Eigen::Vector2d* direction, double* across_gain = nullptr);

}  // namespace canopy::formats
