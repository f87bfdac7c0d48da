// detect's ground (step 2 of detect.h): the DTM raster from PCL's progressive morphological
// filter on the cells' lowest points, holes filled and relaxed, refined by the points near it;
// every point's height above it and its class (ground or other). docs/decisions/detect.md §2.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "detect/detect.h"
#include "detect/frame.h"

namespace canopy::detect {

// The DTM raster.
struct Raster {
  double x0 = 0, y0 = 0, cell = 1;  // lower-left corner (local frame)
  int nx = 0, ny = 0;
  std::vector<double> z;  // cell-centre ground height (local frame), row-major (j * nx + i)

  int ix(double x) const { return std::clamp(int(std::floor((x - x0) / cell)), 0, nx - 1); }
  int iy(double y) const { return std::clamp(int(std::floor((y - y0) / cell)), 0, ny - 1); }
  std::size_t at(int i, int j) const { return std::size_t(j) * std::size_t(nx) + std::size_t(i); }

  // Bilinear between cell centres.
  double height(double x, double y) const {
    const double fx = (x - x0) / cell - 0.5, fy = (y - y0) / cell - 0.5;
    int i0 = nx > 1 ? std::clamp(int(std::floor(fx)), 0, nx - 2) : 0;
    int j0 = ny > 1 ? std::clamp(int(std::floor(fy)), 0, ny - 2) : 0;
    // Linear extrapolation over the outer half cell (points beyond the outermost centres).
    const double tx = nx > 1 ? std::clamp(fx - i0, -0.5, 1.5) : 0.0;
    const double ty = ny > 1 ? std::clamp(fy - j0, -0.5, 1.5) : 0.0;
    const int i1 = std::min(i0 + 1, nx - 1), j1 = std::min(j0 + 1, ny - 1);
    return (1 - ty) * ((1 - tx) * z[at(i0, j0)] + tx * z[at(i1, j0)]) +
           ty * ((1 - tx) * z[at(i0, j1)] + tx * z[at(i1, j1)]);
  }
};

// Ground: the DTM, every point's cell, the cells whose lowest point PMF calls ground, and
// every point's height above the DTM and class.
struct Ground {
  Raster dtm;
  std::vector<std::uint32_t> cell_of;
  std::vector<char> is_ground_cell;
  // The filled cells the hole relaxation moves: all (empty vector) when there are at most
  // kCellsPerPoint per point; else, for a few points spread wide, those within kNearData cells
  // of a cell holding a point, where the DTM is read. 1000 sweeps over every empty cell of such
  // a tile took minutes (2e7 cells for 10 points); this bounds the work by the points, not by
  // the extent.
  std::vector<char> near_data;
  std::vector<float> height;          // per point: height above the DTM (m)
  std::vector<std::uint8_t> classes;  // per point: kClassGround below min_object_height, else kClassOther
  std::size_t ground_cells = 0, filled_cells = 0, ground_points = 0;
  std::size_t cells() const { return std::size_t(dtm.nx) * std::size_t(dtm.ny); }
};

// The DTM (step 2 of detect.h) and every point's height above it and class. Throws
// common::DataError naming `name` when the raster would have too many cells (2e7, or 4e6 + 16
// per point) or fewer than params.min_ground_share of the occupied cells are ground.
Ground find_ground(const LocalFrame& l, const Params& params, const std::string& name);

}  // namespace canopy::detect
