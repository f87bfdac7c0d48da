// Height raster (canopy.height_raster v1): a tile's height above ground on a grid of square
// pixels, the highest point per pixel, as topview draws it (topview --raster-out writes it from
// a tile, topview --raster draws from it; formats/README.md "Height raster"). A text header of
// nine lines, then width x height float32 little-endian values, row-major from the top (north)
// row; NaN = no point in the pixel. Every failure is a DataError naming the file.
#pragma once

#include <string>
#include <vector>

namespace canopy::formats {

struct HeightRaster {
  int width = 0, height = 0;  // pixels, each in [1, 8192], width * height <= 2^24
  double pixel = 0;           // metres a pixel side, > 0
  double x0 = 0, y1 = 0;      // the left edge of column 0, the top edge of row 0 (tile coordinates)
  // The box of the points the raster was made from (x0 <= x1, y0 <= y1).
  double box_x0 = 0, box_y0 = 0, box_x1 = 0, box_y1 = 0;
  double density = 0;         // points per m² over the occupied 1 m cells, >= 0
  std::vector<float> values;  // width * height, row-major from the top row; NaN: no point
  float at(int col, int row) const { return values[static_cast<std::size_t>(row) * width + col]; }
};

// The file's first line: "canopy.height_raster 1".
bool is_height_raster(const std::string& bytes);
// Throws common::Error when the raster breaks the rules above (a writer's bug).
std::string serialize_height_raster(const HeightRaster& raster);
void write_height_raster(const HeightRaster& raster, const std::string& path);  // atomic
// DataError(name, ...): not a height raster, another version, a header line missing, out of
// order or malformed, a value out of its range, data shorter or longer than width x height x 4
// bytes, an infinite value.
HeightRaster parse_height_raster(const std::string& bytes, const std::string& name);
HeightRaster read_height_raster(const std::string& path);

}  // namespace canopy::formats
