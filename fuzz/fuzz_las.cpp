// libFuzzer target: the LAS reader (and the magic dispatch in front of it) on arbitrary bytes.
// Any exception other than canopy's DataError, a crash, a sanitizer report or memory beyond
// -rss_limit_mb is a finding. Seeds: tests/las/data/*.las, *.laz.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/formats/las.h"
#include "canopy/formats/points_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  // Most inputs should reach the LAS parser: keep the signature when the fuzzer dropped it.
  if (size >= 4 && (data[0] & 1)) bytes.replace(0, 4, "LASF");
  try {
    const canopy::formats::PointCloud c = canopy::formats::parse_las(bytes, "fuzz.las");
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
