// libFuzzer target: the EPSG code of a LAS file's CRS records (formats/las_crs.h) on arbitrary
// GeoKey directories and WKT texts. Input: a flags byte (bit 0: the global encoding's WKT bit;
// bit 1: the WKT under libLAS's user id; bit 2: the records are EVLRs, not VLRs; bit 3: and a
// LASF_Projection 34735 VLR of the same payload precedes them), the GeoKey payload's length (2 bytes,
// little-endian; 0xffff = no GeoKey record), that payload, then the WKT (empty = no WKT record). A throw, a
// crash, a sanitizer report, or a result that breaks las_crs's promises (a code of 1 to 6
// digits with its place, else none; a note of one line; a unit of one line, its metres >= 0)
// is a finding. Seeds: make_seeds's las_crs/ (the records of tests/las/data and damaged
// copies).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/las.h"
#include "canopy/formats/las_crs.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  namespace f = canopy::formats;
  f::LasHeaderBlock h;
  h.global_encoding = (data[0] & 1) ? 16 : 0;
  const std::size_t keys = std::size_t(data[1]) | std::size_t(data[2]) << 8;
  const char* rest = reinterpret_cast<const char*>(data + 3);
  const std::size_t left = size - 3;
  std::size_t wkt_at = 0;
  std::vector<f::LasVlr>& records = (data[0] & 4) ? h.evlrs : h.vlrs;
  if (keys != 0xffff) {
    const std::size_t n = keys < left ? keys : left;
    records.push_back({"LASF_Projection", 34735, std::string(rest, n)});
    if ((data[0] & 12) == 12) h.vlrs.push_back({"LASF_Projection", 34735, std::string(rest, n)});
    wkt_at = n;
  }
  if (wkt_at < left) {
    records.push_back(
        {(data[0] & 2) ? "liblas" : "LASF_Projection", 2112, std::string(rest + wkt_at, left - wkt_at)});
  }
  const f::LasCrs c = f::las_crs(h);
  if (c.epsg < 0 || c.epsg > 999999) __builtin_trap();
  if ((c.epsg > 0) != !c.from.empty() || (c.epsg > 0) != !c.code().empty()) __builtin_trap();
  if (c.note.find('\n') != std::string::npos || c.note.size() > 1000) __builtin_trap();
  // A unit: a name and a source of one line, metres >= 0 (> 0 from a WKT).
  auto check_unit = [](const std::optional<f::LinearUnit>& u, bool wkt) {
    if (!u) return;
    if (u->name.find('\n') != std::string::npos || u->source.find('\n') != std::string::npos)
      __builtin_trap();
    if (u->source.empty() || u->name.size() > 300 || u->source.size() > 300) __builtin_trap();
    if (!(u->metres >= 0) || (wkt && !(u->metres > 0))) __builtin_trap();
  };
  check_unit(c.unit, false);
  // The record parsers alone, on the same bytes.
  const f::CrsRecord w = f::read_wkt(std::string(rest, left));
  check_unit(w.unit, true);
  if ((w.code.code > 0) != w.code.problem.empty()) __builtin_trap();
  check_unit(f::read_geokeys(std::string(rest, left)).unit, false);
  return 0;
}
