// libFuzzer target: the LAZ decoder (formats/laz.h) on arbitrary bytes kept LAZ-shaped (LAS
// signature and LASzip's compression bit), then the LAS reader on what it decodes to. Any
// exception other than canopy's DataError, a crash, a sanitizer report, memory beyond
// -rss_limit_mb or an input over -timeout is a finding. Seeds (make_seeds): the small LAZ files
// of tests/las/data (point-wise and layered, fixed and variable chunks, extra bytes, EVLRs)
// and damaged copies of them.
#include <cstddef>
#include <cstdint>
#include <string>

#include "canopy/common/error.h"
#include "canopy/formats/las.h"
#include "canopy/formats/laz.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  if (size >= 4) bytes.replace(0, 4, "LASF");
  if (size > 104) bytes[104] = static_cast<char>(bytes[104] | 0x80);
  try {
    const std::string las = canopy::formats::laz_to_las(bytes, "fuzz.laz");
    // What it returns is plain LAS: no compression bit, no LASzip VLR.
    if (canopy::formats::laszip_compressed(las)) __builtin_trap();
    canopy::formats::parse_las(las, "fuzz.las");
  } catch (const canopy::common::DataError&) {}
  return 0;
}
