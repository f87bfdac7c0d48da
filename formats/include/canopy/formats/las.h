// LAS (ASPRS LIDAR Data Exchange Format) 1.0-1.4, point data record formats 0-10.
// See formats/README.md ("LAS"). Read: scaled integer coordinates -> float64 x y z (scale and
// offset applied in double precision), every standard field of the point format as a column,
// described Extra Bytes as named columns (undescribed bytes and waveform packets skipped).
// Write: LAS 1.4, point format 6 (7 with red green blue, 8 with nir too), scale 0.001 m,
// offset from the data, other columns as Extra Bytes. LAZ (LASzip-compressed LAS) is read too,
// by content (laz.h); it is not written. Path "-" = stdin / stdout. Every failure is a
// DataError naming the file.
#pragma once

#include <string>

#include "canopy/formats/point_cloud.h"

namespace canopy::formats {

// Coordinate resolution of the writer (metres per integer step on x, y and z).
inline constexpr double kLasWriteScale = 0.001;

// True when `bytes` start with the LAS signature "LASF" (LAS or LAZ).
bool is_las(const std::string& bytes);
// True when `bytes` are LAZ: LAS-signed with LASzip's compression bit or VLR (laz.h).
bool is_laz(const std::string& bytes);

PointCloud read_las(const std::string& path);
// Parses an in-memory LAS file; `name` is used in error messages.
PointCloud parse_las(const std::string& bytes, const std::string& name);

// Writes atomically. Rejects NaN/inf coordinates and coordinates that do not fit the 32-bit
// integer grid (extent over ~4 000 km at 1 mm); extra-byte names longer than 32 characters.
void write_las(const PointCloud& cloud, const std::string& path);
// `name` is used in error messages.
std::string serialize_las(const PointCloud& cloud, const std::string& name = "<las>");

}  // namespace canopy::formats
