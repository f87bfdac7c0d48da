// Sensor trajectories (issue 26): where the scanner was at each GPS time, so that verify's
// free-space test can find the direction from a point to the sensor that saw it in a real tile
// (LAS carries gps_time and scan_angle, never sensor vectors). Text format, formats/README.md
// ("Trajectory"):
//
//   # canopy trajectory 1
//   time x y z roll pitch heading
//   # comment lines anywhere after the first line
//   1000.0 500012.5 4399987.0 1180.0 0.1 -0.2 90.0
//   ...
//
// time: GPS seconds (the points' gps_time base); x y z: metres, the points' frame; roll pitch
// heading: degrees, canopy's pose convention R = Rz(heading) Ry(pitch) Rx(roll) (heading from
// +x toward +y, counter-clockwise seen from above; NOT the navigation heading clockwise from
// north: heading = 90 - navigation heading when x = east, y = north). Times strictly increase.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace canopy::formats {

struct TrajectorySample {
  double time = 0;                          // s
  double x = 0, y = 0, z = 0;               // m
  double roll = 0, pitch = 0, heading = 0;  // degrees
};

struct Trajectory {
  std::vector<TrajectorySample> samples;  // time strictly increasing, at least one
  std::vector<std::string> comments;  // '#' lines between the first line and the header line (without "# ")
};

// Bounds on what a reader accepts: a line longer than this is an error (a binary file, a
// file without line breaks), and so is a file larger than kTrajectoryMaxBytes (memory is the
// file plus 56 bytes a sample; a 200 Hz trajectory of 10 hours is ~ 0.5 GB of text).
inline constexpr std::size_t kTrajectoryMaxLine = 4096;
inline constexpr std::size_t kTrajectoryMaxBytes = std::size_t{1} << 30;

// Parses a trajectory; `name` names the file in errors. Throws common::DataError(name,
// "line N: ...") for a missing or wrong first line or header line, a line of other than 7
// values, a value that is not a finite decimal number, a time not after the previous sample's,
// a line too long; "no samples" for a file with none.
Trajectory parse_trajectory(const std::string& text, const std::string& name);
// Reads `path` ("-" = stdin). DataError naming the file for an unreadable or too large file.
Trajectory read_trajectory(const std::string& path);

// The text write_trajectory writes: the first line, `comments` as "# " lines, the header line,
// one sample a line with the shortest decimals that read back to the same doubles. Throws
// std::invalid_argument for non-finite values or times not strictly increasing.
std::string serialize_trajectory(const Trajectory& t);
// Writes atomically (common/atomic_file.h).
void write_trajectory(const Trajectory& t, const std::string& path);

// Sensor position at GPS time `time`: linear interpolation between the two samples around it.
// A time before the first sample or after the last by at most `tolerance` seconds gets the end
// sample's position; further out throws common::DataError(name, "GPS time ... is outside the
// trajectory's span ..."). `name` = the trajectory file.
std::array<double, 3> trajectory_position(const Trajectory& t, double time, double tolerance,
                                          const std::string& name);
// The same with attitude: roll, pitch, heading interpolated along the shorter arc (degrees,
// heading in (-180, 180]).
TrajectorySample trajectory_sample(const Trajectory& t, double time, double tolerance, const std::string& name);

}  // namespace canopy::formats
