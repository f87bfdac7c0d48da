// libFuzzer target: the LAS reader (and the magic dispatch in front of it) on arbitrary bytes.
// Any exception other than canopy's DataError, a crash, a sanitizer report or memory beyond
// -rss_limit_mb is a finding; so is a header block whose CRS EVLRs break their bounds. Seeds:
// tests/las/data/*.las, *.laz.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/formats/las.h"
#include "canopy/formats/las_crs.h"
#include "canopy/formats/points_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  // Most inputs should reach the LAS parser: keep the signature when the fuzzer dropped it.
  if (size >= 4 && (data[0] & 1)) bytes.replace(0, 4, "LASF");
  try {
    // The header block too: its CRS EVLRs are bounded (at most one of each of the three kinds,
    // each of at most kLasCrsEvlrBytes) and las_crs reads them without a throw.
    canopy::formats::LasHeaderBlock h;
    const canopy::formats::PointCloud c = canopy::formats::parse_las(bytes, "fuzz.las", {}, &h);
    if (h.evlrs.size() > 3 || h.evlr_note.find('\n') != std::string::npos) __builtin_trap();
    for (const auto& r : h.evlrs) {
      if (r.payload.size() > canopy::formats::kLasCrsEvlrBytes ||
          !canopy::formats::is_crs_record(r.user_id, r.record_id))
        __builtin_trap();
    }
    const canopy::formats::LasCrs crs = canopy::formats::las_crs(h);
    if (crs.epsg < 0 || crs.epsg > 999999 || crs.note.find('\n') != std::string::npos) __builtin_trap();
    // A cloud that parsed must serialize and read back with the same size.
    if (c.size() < 100000) {
      const std::string again = canopy::formats::serialize_las(c, "fuzz-out.las");
      if (canopy::formats::parse_las(again, "fuzz-out.las").size() != c.size()) __builtin_trap();
      // A field selection reads the same values of the selected columns (packed columns read
      // through value() and, unpacked, through col()).
      const auto sel = canopy::formats::FieldSelection::only({"z", "gps_time", c.names().back()});
      const canopy::formats::PointCloud s = canopy::formats::parse_las(bytes, "fuzz.las", sel);
      if (s.size() != c.size()) __builtin_trap();
      for (std::size_t i = 0; i < s.names().size(); ++i) {
        std::size_t j = 0;
        while (j < c.names().size() && c.names()[j] != s.names()[i]) ++j;
        if (j == c.names().size() || !sel.wants(s.names()[i])) __builtin_trap();
        const std::vector<double>& v = s.col(i);
        for (std::size_t r = 0; r < s.size(); ++r) {
          const double a = c.value(j, r), b = v[r];
          if (!(a == b || (a != a && b != b))) __builtin_trap();
        }
      }
    }
  } catch (const canopy::common::DataError&) {}
  // The dispatcher in front of the LAS reader (PCD and PLY bytes are fuzz_pcd's and fuzz_ply's).
  if (canopy::formats::is_las(bytes)) {
    try {
      canopy::formats::parse_points(bytes, "fuzz", "fuzz");
    } catch (const canopy::common::DataError&) {}
  }
  return 0;
}
