// Binary PPM (P6) images, as POV-Ray writes them (rangetrace's range and label frames):
// maxval 255 or 65535, '#' comments in the header. 8-bit samples are widened to 16 bits
// (v * 257), so both read as the same Image16.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace canopy::formats {

// 16-bit RGB image (row-major, 3 samples per pixel).
struct Image16 {
  int width = 0, height = 0;
  std::vector<std::uint16_t> rgb;
};

// DataError naming `name` when the bytes are not a P6 image or are truncated.
Image16 parse_ppm(const std::string& bytes, const std::string& name);

}  // namespace canopy::formats
