// The coordinate reference system a LAS/LAZ file records, as an EPSG code: the GeoTIFF
// GeoKeyDirectoryTag (LASF_Projection 34735) or the OGC WKT (LASF_Projection 2112, or libLAS's
// copy "liblas" 2112) of LAS 1.4 R15 §2.5, each a VLR of the header block or (LAS 1.4, §2.6) an
// EVLR after the point data; the VLRs first, the EVLRs when the VLRs give no code. No database:
// a code is read only where the file names one. Nothing here throws for a record's content: a
// malformed record gives no code and a one-line note. The same walk of the records gives the
// CRS's horizontal linear unit (detect's feet warning). See formats/README.md ("LAS").
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "canopy/formats/las.h"

namespace canopy::formats {

// A code read from one record, or why none was.
struct EpsgCode {
  int code = 0;      // 1 .. 999999; 0 = none
  std::string from;  // where in the record, e.g. "ProjectedCSTypeGeoKey 2154", "PROJCS AUTHORITY EPSG 2154"
  std::string problem;  // why no code, one line ("" when a code was read)
};

// A CRS's horizontal linear unit.
struct LinearUnit {
  std::string name;    // "metre", "foot", "US survey foot", "EPSG unit 9036", or a WKT's own name
  double metres = 0;   // metres per unit; 0 when the GeoTIFF code is not one known here
  std::string source;  // where it was read, e.g. "GeoTIFF key ProjLinearUnits = 9002"
};

// What one CRS record says: its EPSG code (or why none) and its horizontal linear unit, read in
// one walk of the record.
struct CrsRecord {
  EpsgCode code;
  std::optional<LinearUnit> unit;
};

// From a GeoKeyDirectoryTag payload (4 unsigned shorts of header, the last the key count, then 4
// per key): ProjectedCSTypeGeoKey (3072), else GeographicTypeGeoKey (2048) when
// GTModelTypeGeoKey (1024) says geographic (2) or neither 1024 nor 3072 is there; the value
// inline (location 0, count 1) and an EPSG code (1 .. 32766; 32767 is user-defined). A payload
// shorter than its key count says gives no code. The unit: ProjLinearUnitsGeoKey (3076), inline
// (location 0, count 1): 9001 metre, 9002 foot, 9003 US survey foot, any other code "EPSG unit
// <code>" with metres 0; read from the keys the payload holds even when it is cut short (a
// warning of feet is worth giving from a damaged directory; a code is not).
CrsRecord read_geokeys(const std::string& payload);
// read_geokeys(payload).code.
EpsgCode epsg_from_geokeys(const std::string& payload);

// From an OGC WKT text (WKT 1 or 2; ends at the first NUL): parsed as a tree (keywords, [ ] or
// ( ), quoted strings with "" for a quote, bare numbers and words; at most 32 levels deep), then
// the EPSG AUTHORITY (WKT 1) or ID (WKT 2) that is a direct child of the outermost node when that
// is a projected or geographic CRS (PROJCS, PROJCRS, PROJECTEDCRS, GEOGCS, GEOGCRS,
// GEOGRAPHICCRS); of a compound CRS (COMPD_CS, COMPOUNDCRS) its horizontal part's, else the
// compound's own; of a BOUNDCRS its SOURCECRS's. Codes nested deeper (the datum's, the unit's,
// the base geographic CRS's) are never taken. A text that is not well-formed gives no code.
// The unit: that of the projected CRS the code is read from (PROJCS, PROJCRS, PROJECTEDCRS: the
// outermost node, a compound's horizontal part, a BOUNDCRS's SOURCECRS), its own UNIT or
// LENGTHUNIT (a direct child; WKT 2 may give it on its first AXIS instead), never a nested one
// (the base geographic CRS's angle, a vertical CRS's length): name and factor (a number > 0), the
// node's text (whitespace runs as one space, control bytes as \xNN, at most 200 bytes) as the
// source. A geographic CRS has no linear unit.
CrsRecord read_wkt(const std::string& wkt);
// read_wkt(wkt).code.
EpsgCode epsg_from_wkt(const std::string& wkt);

// Whether a (E)VLR is a CRS record las_crs reads: LASF_Projection 34735 or 2112, liblas 2112.
bool is_crs_record(const std::string& user_id, std::uint16_t record_id);

// What a file's CRS records say.
struct LasCrs {
  int epsg = 0;  // 0 = none read
  // The record and the place, e.g. "LASF_Projection 2112 (OGC WKT): PROJCS AUTHORITY EPSG 2154";
  // an EVLR's record starts "EVLR " ("EVLR LASF_Projection 2112 (OGC WKT): ...").
  std::string from;
  // One line when the file records a CRS but gave no code (each record's problem, then the
  // header block's evlr_note), or when two of its records give different codes (which one was
  // taken and why); "" otherwise.
  std::string note;
  // The horizontal linear unit the records declare, if any (detect warns of one not metres).
  std::optional<LinearUnit> unit;
  // "EPSG:<epsg>", or "" when none.
  std::string code() const;
};

// The CRS of a header block, each record walked once: the VLRs' records, then the EVLRs'
// (LasHeaderBlock::evlrs); within each, the WKT first when the global encoding's WKT bit (16) is
// set (LAS 1.4), the GeoTIFF keys first otherwise. The first record that gives a code is taken;
// a later one giving another code is noted (the reason: a VLR before an EVLR, or the WKT bit).
// A LAS 1.4 writer should put a CRS in one place only: a VLR is the usual one, and a file whose
// VLRs name a code keeps it whatever its EVLRs say (files without CRS EVLRs read as before). The
// unit likewise: the first record in that order that declares one. No record (and no
// evlr_note): none, no note.
LasCrs las_crs(const LasHeaderBlock& header);

// read_las_header_block(path) (the VLRs and the CRS EVLRs), then las_crs; a file that is not LAS
// (PCD, PLY) or whose header the LAS reader refuses: none, no note (the point reader reports
// that). Standard input "-", a FIFO or a device cannot be read again: none (read_points hands
// back the header block it read, EVLRs too: points_io.h).
LasCrs read_las_crs(const std::string& path);

// Whether `text` is an EPSG code as canopy writes and accepts one: "EPSG:" and 1 to 6 digits,
// the first not 0 (the index's "crs", collect --crs, the GeoJSON's "crs" member).
bool is_epsg_code(const std::string& text);

}  // namespace canopy::formats
