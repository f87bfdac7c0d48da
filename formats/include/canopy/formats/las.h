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

// A LAS file's header block: its version, point data format and VLRs, and the CRS records
// among its EVLRs.
struct LasHeaderBlock {
  int major = 0, minor = 0, point_format = 0;  // a LAZ file's without LASzip's compression bits
  std::uint16_t global_encoding = 0;           // bit 4 (16): the CRS is WKT, not GeoTIFF keys
  std::vector<LasVlr> vlrs;
  // LAS 1.4's EVLRs (after the point data) that are CRS records (las_crs.h's is_crs_record):
  // the first of each kind (LASF_Projection 34735, LASF_Projection 2112, liblas 2112) in file
  // order, each of at most kLasCrsEvlrBytes; no other EVLR is kept.
  std::vector<LasVlr> evlrs;
  // One line when a CRS EVLR was not read: one over kLasCrsEvlrBytes ("EVLR 2 (LASF_Projection
  // 2112) of ... bytes is over ..."), or (read_las_header_block only; the point reader refuses
  // such a file) EVLRs that do not lie in the file ("EVLRs not read: ..."); "" otherwise.
  std::string evlr_note;
};
// The largest CRS EVLR payload read (a WKT is a few kB; a VLR holds at most 64 KiB).
inline constexpr std::size_t kLasCrsEvlrBytes = std::size_t(1) << 20;

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
// again (their CRS EVLRs too: they are read whole); never a failure of its own (the reader has
// made the same checks, the EVLRs' too).
PointCloud read_las(const std::string& path, const FieldSelection& fields = {},
                    LasHeaderBlock* header = nullptr);
// The same, `chunk_bytes` of point records at a time (at least one record): for tests of the
// chunk edges.
PointCloud read_las(const std::string& path, std::size_t chunk_bytes, const FieldSelection& fields = {},
                    LasHeaderBlock* header = nullptr);
inline constexpr std::size_t kLasReadChunk = std::size_t(256) << 10;

// Reads only the header and the VLRs of the LAS or LAZ file `path` (LAZ keeps them
// uncompressed; the points are not read): at most `max_bytes` of the file (the header always
// whole); VLRs that end beyond them are not returned. Then (LAS 1.4) the EVLRs' headers, and
// the payloads of the CRS EVLRs (LasHeaderBlock::evlrs; LAZ keeps its EVLRs uncompressed too).
// Every failure is a DataError naming the file: not LAS, and every check read_las makes of the
// header and the VLRs (not those of the point data). EVLRs that do not lie in the file (the
// first's offset inside the point records or past the end, one running past the end, a count
// the file cannot hold) are no failure: evlr_note says why, and the CRS EVLRs walked before
// the problem are kept.
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
