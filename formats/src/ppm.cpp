#include "canopy/formats/ppm.h"

#include <cctype>
#include <stdexcept>

#include "canopy/common/error.h"

namespace canopy::formats {

Image16 parse_ppm(const std::string& bytes, const std::string& name) {
  std::size_t pos = 0;
  auto token = [&]() {
    while (pos < bytes.size()) {
      if (bytes[pos] == '#') {
        while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
      } else if (std::isspace(static_cast<unsigned char>(bytes[pos]))) {
        ++pos;
      } else {
        break;
      }
    }
    std::string t;
    while (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos]))) t += bytes[pos++];
    return t;
  };
  if (token() != "P6") throw common::DataError(name, "not a binary PPM (P6) image");
  Image16 img;
  int maxval = 0;
  try {
    img.width = std::stoi(token());
    img.height = std::stoi(token());
    maxval = std::stoi(token());
  } catch (const std::logic_error&) { throw common::DataError(name, "malformed PPM header"); }
  ++pos;  // the single whitespace after maxval
  if (img.width <= 0 || img.height <= 0 || (maxval != 255 && maxval != 65535)) {
    throw common::DataError(name, "unsupported PPM size or maxval");
  }
  const std::size_t n = static_cast<std::size_t>(img.width) * img.height * 3;
  const std::size_t bpp = maxval == 65535 ? 2 : 1;
  if (bytes.size() < pos + n * bpp) throw common::DataError(name, "PPM data truncated");
  img.rgb.resize(n);
  const auto* d = reinterpret_cast<const unsigned char*>(bytes.data() + pos);
  for (std::size_t i = 0; i < n; ++i) {
    img.rgb[i] = bpp == 2 ? static_cast<std::uint16_t>(d[2 * i] << 8 | d[2 * i + 1])
                          : static_cast<std::uint16_t>(d[i] * 257);
  }
  return img;
}

}  // namespace canopy::formats
