// PCD (Point Cloud Data, PCL's format, version 0.7). See formats/README.md.
// Reads DATA ascii, binary and binary_compressed with any set of fields (COUNT > 1 fields
// become columns name_0, name_1, ...; PCL padding fields "_" are skipped). Writes binary.
// Path "-" = stdin / stdout. Every failure is a DataError naming the file.
#pragma once

#include <string>

#include "canopy/formats/point_cloud.h"

namespace canopy::formats {

PointCloud read_pcd(const std::string& path);
// Parses an in-memory PCD file; `name` is used in error messages.
PointCloud parse_pcd(const std::string& bytes, const std::string& name);

// Writes atomically (temporary file + rename). Rejects NaN/inf coordinates x, y, z.
void write_pcd(const PointCloud& cloud, const std::string& path);
std::string serialize_pcd(const PointCloud& cloud);

}  // namespace canopy::formats
