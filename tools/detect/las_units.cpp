#include "detect/las_units.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

namespace canopy::detect {
namespace {

constexpr std::size_t kMaxHeaderBytes = 16u << 20;
constexpr std::size_t kVlrHeader = 54;

std::uint32_t u16(const unsigned char* p) { return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8; }
std::uint32_t u32(const unsigned char* p) { return u16(p) | u16(p + 2) << 16; }

std::optional<LinearUnit> from_epsg(std::uint32_t code, const std::string& source) {
  switch (code) {
    case 9001: return LinearUnit{"metre", 1.0, source};
    case 9002: return LinearUnit{"foot", 0.3048, source};
    case 9003: return LinearUnit{"US survey foot", 1200.0 / 3937.0, source};
    default: return LinearUnit{"EPSG unit " + std::to_string(code), 0.0, source};
  }
}

// A projected WKT's linear unit: the last UNIT["name",factor] (GEOGCS's angular unit comes
// before it). Only PROJCS (not compound or geographic systems).
std::optional<LinearUnit> from_wkt(const std::string& wkt) {
  if (wkt.rfind("PROJCS[", 0) != 0) return std::nullopt;
  const std::size_t at = wkt.rfind("UNIT[\"");
  if (at == std::string::npos) return std::nullopt;
  const std::size_t q = wkt.find('"', at + 6);
  if (q == std::string::npos || q + 1 >= wkt.size() || wkt[q + 1] != ',') return std::nullopt;
  const std::string name = wkt.substr(at + 6, q - at - 6);
  double factor = 0;
  try {
    factor = std::stod(wkt.substr(q + 2, 32));
  } catch (...) { return std::nullopt; }
  if (!(factor > 0)) return std::nullopt;
  return LinearUnit{name, factor,
                    "WKT UNIT[\"" + name + "\"," + wkt.substr(q + 2, wkt.find(']', q) - q - 2) + "]"};
}

}  // namespace

std::optional<LinearUnit> las_linear_unit(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  unsigned char h[104];
  if (!f.read(reinterpret_cast<char*>(h), sizeof h) || std::memcmp(h, "LASF", 4) != 0) return std::nullopt;
  const std::size_t header_size = u16(h + 94), data_offset = u32(h + 96), vlrs = u32(h + 100);
  if (header_size < 104 || data_offset < header_size) return std::nullopt;
  std::vector<unsigned char> b(std::min(data_offset, kMaxHeaderBytes));
  f.seekg(0);
  if (!f.read(reinterpret_cast<char*>(b.data()), std::streamsize(b.size()))) return std::nullopt;
  std::optional<LinearUnit> wkt;
  std::size_t pos = header_size;
  for (std::size_t i = 0; i < vlrs && pos + kVlrHeader <= b.size(); ++i) {
    const unsigned char* v = b.data() + pos;
    const std::size_t len = u16(v + 20);
    if (pos + kVlrHeader + len > b.size()) break;
    const std::uint32_t id = u16(v + 18);
    const unsigned char* d = v + kVlrHeader;
    const bool projection = std::strncmp(reinterpret_cast<const char*>(v + 2), "LASF_Projection", 16) == 0;
    if (projection && id == 34735 && len >= 8) {
      // GeoKeyDirectoryTag: 4 shorts of header (the last the key count), then 4 per key.
      const std::size_t keys = std::min<std::size_t>(u16(d + 6), (len - 8) / 8);
      for (std::size_t k = 0; k < keys; ++k) {
        const unsigned char* e = d + 8 + 8 * k;
        if (u16(e) == 3076 && u16(e + 2) == 0) {  // ProjLinearUnitsGeoKey, value inline
          return from_epsg(u16(e + 6), "GeoTIFF key ProjLinearUnits = " + std::to_string(u16(e + 6)));
        }
      }
    } else if (id == 2112 && !wkt) {  // OGC coordinate system WKT (LASF_Projection, or libLAS's copy)
      wkt = from_wkt(
          std::string(reinterpret_cast<const char*>(d), strnlen(reinterpret_cast<const char*>(d), len)));
    }
    pos += kVlrHeader + len;
  }
  return wkt;
}

}  // namespace canopy::detect
