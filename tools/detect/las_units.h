// The linear unit a LAS file's georeferencing declares (GeoTIFF keys or OGC WKT VLR), read
// from its header and VLRs only (formats::read_las_header_block: at most 16 MiB).
#pragma once

#include <optional>
#include <string>

namespace canopy::detect {

struct LinearUnit {
  std::string name;    // "metre", "foot", "US survey foot", or "EPSG unit 9036"
  double metres = 0;   // metres per unit; 0 when the code is not one detect knows
  std::string source;  // where it was read, e.g. "GeoTIFF key ProjLinearUnits = 9002"
};

// The declared horizontal unit of `path` when it is a LAS file that declares one; nullopt for
// other files, LAS files without georeferencing and anything unreadable (the reader reports
// those).
std::optional<LinearUnit> las_linear_unit(const std::string& path);

}  // namespace canopy::detect
