// LAS (ASPRS LIDAR Data Exchange Format) 1.0-1.4, point data record formats 0-10.
// See formats/README.md ("LAS"). Read: scaled integer coordinates -> float64 x y z (scale and
// offset applied in double precision), every standard field of the point format as a column,
// described Extra Bytes as named columns (undescribed bytes and waveform packets skipped).
// Write: LAS 1.4, point format 6 (7 with red green blue, 8 with nir too), scale 0.001 m,
// offset from the data, other columns as Extra Bytes. LAZ (LASzip-compressed LAS) is read too,
// by content (laz.h); it is not written. Path "-" = stdin / stdout. Every failure is a
// DataError naming the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"

namespace canopy::formats {

// Coordinate resolution of the writer (metres per integer step on x, y and z).
inline constexpr double kLasWriteScale = 0.001;

// True when `bytes` start with the LAS signature "LASF" (LAS or LAZ).
bool is_las(const std::string& bytes);
// True when `bytes` are LAZ: LAS-signed with LASzip's compression bit or VLR (laz.h).
bool is_laz(const std::string& bytes);

// One variable-length record (VLR) of a LAS file's header block.
struct LasVlr {
  std::string user_id;  // up to 16 bytes, up to the first NUL
  std::uint16_t record_id = 0;
  std::string payload;
};

// A LAS file's header block: its version, point data format and VLRs.
struct LasHeaderBlock {
  int major = 0, minor = 0, point_format = 0;  // a LAZ file's without LASzip's compression bits
  std::uint16_t global_encoding = 0;           // bit 4 (16): the CRS is WKT, not GeoTIFF keys
  std::vector<LasVlr> vlrs;
};

// Reads a LAS or LAZ file. A regular LAS file is read straight from the file: the header and
// VLRs, the EVLRs (LAS 1.4; they follow the points), then the point records kLasReadChunk bytes
// (whole records; a sixteenth of the records, at least 64 KiB, when that is less) at a time,
// each decoded into the columns, which are filled without being
// zero-filled first; memory: the columns plus one chunk. Standard input, FIFOs and LAZ files
// are read whole first, then parsed (parse_las). The values and errors are parse_las's.
// The columns are packed (point_cloud.h: each field at its width in the record, turned into
// doubles by the first col() that asks for it; x y z the int32 with the header's scale and
// offset; gps_time doubles): memory about 1.2-1.5x the point records. `fields`: only those
// columns are made (the file's checks are the same; a field the file lacks is no error).
// `header` (not null): also the file's header block, what read_las_header_block(path) gives
// (below), from the bytes already read: standard input and FIFOs too, which cannot be read
// again; never a failure of its own (the reader has made the same checks).
PointCloud read_las(const std::string& path, const FieldSelection& fields = {},
                    LasHeaderBlock* header = nullptr);
// The same, `chunk_bytes` of point records at a time (at least one record): for tests of the
// chunk edges.
PointCloud read_las(const std::string& path, std::size_t chunk_bytes, const FieldSelection& fields = {},
                    LasHeaderBlock* header = nullptr);
inline constexpr std::size_t kLasReadChunk = std::size_t(256) << 10;

// Reads only the header and the VLRs of the LAS or LAZ file `path` (LAZ keeps them
// uncompressed; the points are not read): at most `max_bytes` of the file (the header always
// whole); VLRs that end beyond them are not returned. Every failure is a DataError naming the
// file: not LAS, and every check read_las makes of the header and the VLRs (not those of the
// point data and EVLRs).
inline constexpr std::size_t kLasHeaderBlockBytes = std::size_t(16) << 20;
LasHeaderBlock read_las_header_block(const std::string& path, std::size_t max_bytes = kLasHeaderBlockBytes);
// Parses an in-memory LAS file; `name` is used in error messages. `header`: as read_las's.
PointCloud parse_las(const std::string& bytes, const std::string& name);
PointCloud parse_las(const std::string& bytes, const std::string& name, const FieldSelection& fields,
                     LasHeaderBlock* header = nullptr);

// Writes atomically. Rejects NaN/inf coordinates and coordinates that do not fit the 32-bit
// integer grid (extent over ~4 000 km at 1 mm); extra-byte names longer than 32 characters.
void write_las(const PointCloud& cloud, const std::string& path);
// `name` is used in error messages.
std::string serialize_las(const PointCloud& cloud, const std::string& name = "<las>");

}  // namespace canopy::formats
