#include "detect/density.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "detect/rows.h"

namespace canopy::detect {
namespace {

// The tile's density on 1 m cells of the local frame (after the ground: a cell is open ground
// when every point in it lies below min_object_height).
Density measure_density(const formats::PointCloud& tile, const LocalFrame& l,
                        const std::vector<float>& height, const Params& params) {
  Density d;
  const std::size_t n = l.x.size();
  const double x0 = l.lo.x() - l.origin.x(), y0 = l.lo.y() - l.origin.y();
  const std::size_t nx = std::size_t(std::floor(l.hi.x() - l.lo.x())) + 1;
  const std::size_t ny = std::size_t(std::floor(l.hi.y() - l.lo.y())) + 1;
  std::vector<std::uint32_t> count(nx * ny, 0), first(nx * ny, 0);
  std::vector<char> raised(nx * ny, 0);
  const std::vector<double>* ret = tile.has("return_number") ? &tile.col("return_number") : nullptr;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t cx = std::min(nx - 1, std::size_t(std::max(0.0, l.x[i] - x0)));
    const std::size_t cy = std::min(ny - 1, std::size_t(std::max(0.0, l.y[i] - y0)));
    const std::size_t c = cy * nx + cx;
    ++count[c];
    if (ret && (*ret)[i] <= 1) ++first[c];
    if (height[i] >= params.min_object_height) raised[c] = 1;
  }
  std::size_t open_points = 0, firsts = 0;
  for (std::size_t c = 0; c < count.size(); ++c) {
    if (!count[c]) continue;
    ++d.occupied_cells;
    firsts += first[c];
    if (!raised[c]) {
      ++d.open_cells;
      open_points += count[c];
    }
  }
  d.all = d.occupied_cells ? double(n) / double(d.occupied_cells) : 0.0;
  // Open ground needs a few cells to say anything (a tile of only objects has none).
  constexpr std::size_t kFewestOpenCells = 10;
  if (d.open_cells >= kFewestOpenCells) d.ground = double(open_points) / double(d.open_cells);
  if (ret && d.occupied_cells) d.first = double(firsts) / double(d.occupied_cells);
  return d;
}

}  // namespace

double voxel_for_density(double d) {
  return d > 0 ? std::max(kDenseVoxel, kVoxelDensityScale / std::sqrt(d)) : kDenseVoxel;
}

double planarity_for_density(double d) { return d >= kPlanarityDensity ? kDensePlanarity : 0.0; }

double cell_for_density(double d) {
  return d > 0 ? std::clamp(std::sqrt(kCellReturns / d), kDenseCell, kSparseCell) : kDenseCell;
}

// Points per occupied 1 m cell of the local frame (the same cells as measure_density's `all`).
// Before the ground, the extent is not yet bounded (find_ground refuses too many DTM cells), so
// the occupied cells are counted by sorting the points' cell coordinates: memory O(points).
double occupied_density(const LocalFrame& l) {
  const std::size_t n = l.x.size();
  if (n == 0) return 0.0;
  const double x0 = l.lo.x() - l.origin.x(), y0 = l.lo.y() - l.origin.y();
  std::vector<std::pair<double, double>> cell(n);
  for (std::size_t i = 0; i < n; ++i) {
    cell[i] = {std::floor(std::max(0.0, l.x[i] - x0)), std::floor(std::max(0.0, l.y[i] - y0))};
  }
  std::sort(cell.begin(), cell.end());
  const std::size_t cells = std::size_t(std::unique(cell.begin(), cell.end()) - cell.begin());
  return double(n) / double(cells);
}

Density density_rule(const formats::PointCloud& tile, const LocalFrame& l, const std::vector<float>& height,
                     const Params& params) {
  Density d = measure_density(tile, l, height, params);
  d.rule = d.ground ? *d.ground : d.all;
  d.voxel = params.voxel_from_density ? voxel_for_density(d.rule) : params.voxel;
  d.min_planarity = params.planarity_from_density ? planarity_for_density(d.rule) : params.min_planarity;
  d.voxel_by_rule = params.voxel_from_density;
  d.planarity_by_rule = params.planarity_from_density;
  d.cell = params.cell;
  d.cell_by_rule = params.cell_from_density;
  d.split_rows_by_rule = params.split_rows_from_density;
  d.split_rows = params.split_rows_from_density ? d.rule < kRowSplitDensity : params.split_rows;
  d.row_tolerance = row_tolerance_for_density(d.rule);  // always the density's
  return d;
}

}  // namespace canopy::detect
