// LAZ: LAS whose point records are compressed by LASzip (M. Isenburg, PE&RS 79(2), 2013).
// Read only, by content: a LAS file whose point format byte has bit 7 (or 6) set, or that
// holds the "laszip encoded" VLR (record 22204), is LAZ; read_las / parse_las and every tool
// that reads LAS read it. Decoded: LAS 1.0-1.4, point formats 0-3 (point-wise items, version
// 2) and 6-8 (layered items, versions 3 and 4), fixed or variable chunks, with or without extra
// bytes; not waveform items (formats 4, 5, 9, 10) nor LASzip 1.x's item version 1.
// Decision, sources and figures: docs/decisions/laz.md.
#pragma once

#include <string>

namespace canopy::formats {

// True when `bytes` (a whole file or at least its header and VLRs) are LAS-signed and
// LASzip-compressed: compression bit in the point format byte or a LASzip VLR.
bool laszip_compressed(const std::string& bytes);

// The uncompressed LAS file a LAZ file stands for: the same header (point format without the
// compression bits, offsets moved), the VLRs but LASzip's, the decoded point records (byte for
// byte those LASzip compressed), then the EVLRs. `name` is used in error messages.
// Bad input throws common::DataError naming the file, the chunk and the problem. Memory is
// bounded by the file: the chunk table must fit the point data, and a chunk may not claim
// more than kLazMaxExpansion bytes of records per compressed byte.
std::string laz_to_las(const std::string& bytes, const std::string& name);

// Largest ratio (bytes of point records) / (compressed bytes) accepted for a chunk.
inline constexpr unsigned kLazMaxExpansion = 1000;

}  // namespace canopy::formats
