#include "detect/las_units.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "canopy/common/error.h"
#include "canopy/formats/las.h"

namespace canopy::detect {
namespace {

std::uint32_t u16(const unsigned char* p) { return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8; }

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

// The GeoTIFF GeoKeyDirectoryTag (LASF_Projection 34735): 4 shorts of header (the last the key
// count), then 4 per key; ProjLinearUnitsGeoKey (3076) with its value inline.
std::optional<LinearUnit> from_geokeys(const std::string& payload) {
  const std::size_t len = payload.size();
  if (len < 8) return std::nullopt;
  const auto* d = reinterpret_cast<const unsigned char*>(payload.data());
  const std::size_t keys = std::min<std::size_t>(u16(d + 6), (len - 8) / 8);
  for (std::size_t k = 0; k < keys; ++k) {
    const unsigned char* e = d + 8 + 8 * k;
    if (u16(e) == 3076 && u16(e + 2) == 0) {
      return from_epsg(u16(e + 6), "GeoTIFF key ProjLinearUnits = " + std::to_string(u16(e + 6)));
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<LinearUnit> las_linear_unit(const std::string& path) {
  formats::LasHeaderBlock header;
  try {
    header = formats::read_las_header_block(path);
  } catch (const common::DataError&) {
    return std::nullopt;  // not LAS, or a header the reader refuses (it reports that itself)
  }
  std::optional<LinearUnit> wkt;
  for (const formats::LasVlr& v : header.vlrs) {
    if (v.user_id == "LASF_Projection" && v.record_id == 34735) {
      if (auto unit = from_geokeys(v.payload)) return unit;
    } else if (v.record_id == 2112 && !wkt) {  // OGC coordinate system WKT (LASF_Projection, or libLAS's copy)
      wkt = from_wkt(v.payload.substr(0, strnlen(v.payload.data(), v.payload.size())));
    }
  }
  return wkt;
}

}  // namespace canopy::detect
