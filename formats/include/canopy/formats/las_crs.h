// The coordinate reference system a LAS/LAZ file records, as an EPSG code: the GeoTIFF
// GeoKeyDirectoryTag (VLR LASF_Projection 34735) or the OGC WKT (VLR LASF_Projection 2112, or
// libLAS's copy "liblas" 2112) of LAS 1.4 R15 §2.5. Only the header's VLRs are read (not EVLRs).
// No database: a code is read only where the file names one. Nothing here throws for a record's
// content: a malformed record gives no code and a one-line note. See formats/README.md ("LAS").
#pragma once

#include <string>

#include "canopy/formats/las.h"

namespace canopy::formats {

// A code read from one record, or why none was.
struct EpsgCode {
  int code = 0;      // 1 .. 999999; 0 = none
  std::string from;  // where in the record, e.g. "ProjectedCSTypeGeoKey 2154", "PROJCS AUTHORITY EPSG 2154"
  std::string problem;  // why no code, one line ("" when a code was read)
};

// From a GeoKeyDirectoryTag payload (4 unsigned shorts of header, the last the key count, then 4
// per key): ProjectedCSTypeGeoKey (3072), else GeographicTypeGeoKey (2048) when
// GTModelTypeGeoKey (1024) says geographic (2) or neither 1024 nor 3072 is there; the value
// inline (location 0, count 1) and an EPSG code (1 .. 32766; 32767 is user-defined). A payload
// shorter than its key count says gives no code.
EpsgCode epsg_from_geokeys(const std::string& payload);

// From an OGC WKT text (WKT 1 or 2; ends at the first NUL): parsed as a tree (keywords, [ ] or
// ( ), quoted strings with "" for a quote, bare numbers and words; at most 32 levels deep), then
// the EPSG AUTHORITY (WKT 1) or ID (WKT 2) that is a direct child of the outermost node when that
// is a projected or geographic CRS (PROJCS, PROJCRS, PROJECTEDCRS, GEOGCS, GEOGCRS,
// GEOGRAPHICCRS); of a compound CRS (COMPD_CS, COMPOUNDCRS) its horizontal part's, else the
// compound's own; of a BOUNDCRS its SOURCECRS's. Codes nested deeper (the datum's, the unit's,
// the base geographic CRS's) are never taken. A text that is not well-formed gives no code.
EpsgCode epsg_from_wkt(const std::string& wkt);

// What a file's CRS records say.
struct LasCrs {
  int epsg = 0;  // 0 = none read
  std::string from;  // the record and the place, e.g. "LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154"
  // One line when the file records a CRS but gave no code, or when its GeoTIFF keys and WKT
  // give different codes (which one was taken and why); "" otherwise.
  std::string note;
  // "EPSG:<epsg>", or "" when none.
  std::string code() const;
};

// The CRS of a header block: the WKT first when the global encoding's WKT bit (16) is set, the
// GeoTIFF keys first otherwise; the other record when the first gives no code. No record: none,
// no note.
LasCrs las_crs(const LasHeaderBlock& header);

// read_las_header_block(path), then las_crs; a file that is not LAS (PCD, PLY, stdin "-") or
// whose header the LAS reader refuses: none, no note (the point reader reports that).
LasCrs read_las_crs(const std::string& path);

}  // namespace canopy::formats
