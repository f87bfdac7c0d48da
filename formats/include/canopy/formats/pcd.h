// PCD (Point Cloud Data, PCL's format, version 0.7). See formats/README.md.
// Reads DATA ascii, binary and binary_compressed with any set of fields (COUNT > 1 fields
// become columns name_0, name_1, ...; PCL padding fields "_" are skipped); zero bytes after
// binary data (PCL's writer pads to a page) are accepted. Writes binary (default),
// binary_compressed (PCL tools' default) or ascii.
// Path "-" = stdin / stdout. Every failure is a DataError naming the file; memory is bounded
// by what the file can hold (a header cannot make the reader allocate more than its data).
#pragma once

#include <string>

#include "canopy/formats/point_cloud.h"

namespace canopy::formats {

PointCloud read_pcd(const std::string& path);
// The same, keeping only the fields in `fields` that the file has. DATA binary from a regular
// file is read in chunks and makes only those columns (when x, y and z are among them: the
// coordinates are always checked); otherwise the file is read whole and the others dropped.
PointCloud read_pcd(const std::string& path, const FieldSelection& fields);
// Parses an in-memory PCD file; `name` is used in error messages.
PointCloud parse_pcd(const std::string& bytes, const std::string& name);

enum class PcdEncoding { binary, binary_compressed, ascii };

struct PcdWriteOptions {
  PcdEncoding encoding = PcdEncoding::binary;  // the DATA line
};

// Writes atomically (temporary file + rename). Rejects NaN/inf coordinates x, y, z.
// Throws DataError(name) naming the first point whose x, y or z is NaN or infinite (the readers
// and writers of every point format refuse them).
void check_coordinates(const PointCloud& cloud, const std::string& name);
void write_pcd(const PointCloud& cloud, const std::string& path);
void write_pcd(const PointCloud& cloud, const std::string& path, const PcdWriteOptions& options);
std::string serialize_pcd(const PointCloud& cloud);
std::string serialize_pcd(const PointCloud& cloud, const PcdWriteOptions& options);

}  // namespace canopy::formats
