#include "detect/ground.h"

#include <limits>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/segmentation/progressive_morphological_filter.h>

#include "canopy/common/error.h"
#include "canopy/formats/csv_table.h"

namespace canopy::detect {
namespace {

using common::DataError;
using formats::format_number;

constexpr double kMaxCells = 2e7;      // DTM raster limit (bounded memory)
constexpr double kFreeCells = 4e6;     // DTM cells any tile may have (1 km x 1 km at 0.5 m) ...
constexpr double kCellsPerPoint = 16;  // ... and these per point beyond (a sparse tile)
constexpr int kNearData = 2;           // relaxed DTM holes: this many cells from a point

// True when one of the 8-neighbours of cell (i, j) is known.
bool next_to_known(const Raster& r, const std::vector<char>& known, int i, int j) {
  for (int dj = -1; dj <= 1; ++dj)
    for (int di = -1; di <= 1; ++di) {
      const int a = i + di, b = j + dj;
      if (a >= 0 && b >= 0 && a < r.nx && b < r.ny && known[r.at(a, b)]) return true;
    }
  return false;
}

// Mean height of the known 8-neighbours of cell c.
double known_mean(const Raster& r, const std::vector<char>& known, std::size_t c) {
  const int i = int(c % std::size_t(r.nx)), j = int(c / std::size_t(r.nx));
  double sum = 0;
  int n = 0;
  for (int dj = -1; dj <= 1; ++dj)
    for (int di = -1; di <= 1; ++di) {
      const int a = i + di, b = j + dj;
      if (a >= 0 && b >= 0 && a < r.nx && b < r.ny && known[r.at(a, b)]) {
        sum += r.z[r.at(a, b)];
        ++n;
      }
    }
  return sum / n;
}

// The unknown 8-neighbours of the frontier's cells not queued yet (now queued).
std::vector<std::size_t> next_layer(const Raster& r, const std::vector<char>& known,
                                    std::vector<char>& queued, const std::vector<std::size_t>& frontier) {
  std::vector<std::size_t> next;
  for (std::size_t c : frontier) {
    const int i = int(c % std::size_t(r.nx)), j = int(c / std::size_t(r.nx));
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        const int a = i + di, b = j + dj;
        if (a < 0 || b < 0 || a >= r.nx || b >= r.ny) continue;
        const std::size_t d = r.at(a, b);
        if (!known[d] && !queued[d]) {
          queued[d] = 1;
          next.push_back(d);
        }
      }
  }
  return next;
}

// Harmonic relaxation of the filled cells (Gauss-Seidel on the 4-neighbour Laplacian, the
// known cells fixed): planes and slopes continue under a hole instead of flattening. Only the
// filled cells with `near` set move (all when it is empty); the others keep their
// breadth-first value and act as fixed boundary values (Ground::near_data says which).
void relax_holes(Raster& r, const std::vector<char>& filled, const std::vector<char>& near) {
  std::vector<std::size_t> holes;
  for (std::size_t c = 0; c < r.z.size(); ++c) {
    if (filled[c] && (near.empty() || near[c])) holes.push_back(c);
  }
  for (int it = 0; it < 1000 && !holes.empty(); ++it) {
    double change = 0;
    for (std::size_t c : holes) {
      const int i = int(c % std::size_t(r.nx)), j = int(c / std::size_t(r.nx));
      double sum = 0;
      int n = 0;
      if (i > 0) {
        sum += r.z[c - 1];
        ++n;
      }
      if (i + 1 < r.nx) {
        sum += r.z[c + 1];
        ++n;
      }
      if (j > 0) {
        sum += r.z[c - std::size_t(r.nx)];
        ++n;
      }
      if (j + 1 < r.ny) {
        sum += r.z[c + std::size_t(r.nx)];
        ++n;
      }
      const double v = sum / n;
      change = std::max(change, std::abs(v - r.z[c]));
      r.z[c] = v;
    }
    if (change < 1e-4) break;
  }
}

// Fills the NaN cells breadth-first from the known ones: each newly reached cell takes the
// mean of its 8-neighbours known before its layer; then relax_holes on those `near` data.
// Returns the number of filled cells.
std::size_t fill_holes(Raster& r, const std::vector<char>& near) {
  std::vector<std::size_t> frontier;
  std::vector<char> known(r.z.size());
  for (std::size_t c = 0; c < r.z.size(); ++c) known[c] = !std::isnan(r.z[c]);
  for (int j = 0; j < r.ny; ++j) {
    for (int i = 0; i < r.nx; ++i) {
      if (!known[r.at(i, j)] && next_to_known(r, known, i, j)) frontier.push_back(r.at(i, j));
    }
  }
  std::size_t filled = 0;
  std::vector<char> queued(r.z.size(), 0);
  for (std::size_t c : frontier) queued[c] = 1;
  while (!frontier.empty()) {
    std::vector<double> values(frontier.size());
    for (std::size_t f = 0; f < frontier.size(); ++f) values[f] = known_mean(r, known, frontier[f]);
    for (std::size_t f = 0; f < frontier.size(); ++f) {
      r.z[frontier[f]] = values[f];
      known[frontier[f]] = 1;
      ++filled;
    }
    frontier = next_layer(r, known, queued, frontier);
  }
  relax_holes(r, queued, near);
  return filled;
}

// The DTM raster over the tile's bounds, heights not set; DataError when it has too many cells.
Raster dtm_raster(const LocalFrame& l, const Params& params, const std::string& name) {
  Raster dtm;
  dtm.cell = params.cell;
  dtm.x0 = l.lo.x() - l.origin.x();
  dtm.y0 = l.lo.y() - l.origin.y();
  const double nxd = std::floor((l.hi.x() - l.lo.x()) / params.cell) + 1;
  const double nyd = std::floor((l.hi.y() - l.lo.y()) / params.cell) + 1;
  if (nxd * nyd > kMaxCells) {
    throw DataError(name, "the tile spans " + format_number("%.0f", l.hi.x() - l.lo.x()) + " m x " +
                              format_number("%.0f", l.hi.y() - l.lo.y()) +
                              " m: " + format_number("%.3g", nxd * nyd) + " DTM cells of " +
                              format_number("%g", params.cell) + " m (limit " +
                              format_number("%.0g", kMaxCells) + "); split the tile or raise --cell");
  }
  // The work on the raster (filling, refining, bucketing) is per cell: bound it by the points.
  const double n = double(l.x.size());
  const double allowed = kFreeCells + kCellsPerPoint * n;
  if (nxd * nyd > allowed) {
    throw DataError(
        name, "its " + format_number("%.0f", n) + " points spread over " +
                  format_number("%.0f", l.hi.x() - l.lo.x()) + " m x " +
                  format_number("%.0f", l.hi.y() - l.lo.y()) + " m: " + format_number("%.3g", nxd * nyd) +
                  " DTM cells of " + format_number("%g", params.cell) + " m, more than such a sparse tile " +
                  "may have (" + format_number("%.0g", kFreeCells) + " + " +
                  format_number("%.0f", kCellsPerPoint) + " per point = " + format_number("%.3g", allowed) +
                  "); crop the tile to where its points are, or raise --cell");
  }
  dtm.nx = int(nxd);
  dtm.ny = int(nyd);
  return dtm;
}

constexpr std::uint32_t kNoPoint = std::numeric_limits<std::uint32_t>::max();

// The cells within kNearData cells (Chebyshev distance) of a cell holding a point: a
// separable dilation of the occupied cells, O(cells).
std::vector<char> cells_near_data(const Raster& r, const std::vector<std::uint32_t>& lowest) {
  const int nx = r.nx, ny = r.ny;
  std::vector<char> rows(lowest.size(), 0), out(lowest.size(), 0);
  for (int j = 0; j < ny; ++j) {
    int last = -1 - 2 * kNearData;  // the last occupied column up to i
    for (int i = 0; i < nx + kNearData; ++i) {
      if (i < nx && lowest[r.at(i, j)] != kNoPoint) last = i;
      // Column t = i - D is near when an occupied column lies in [t - D, t + D = i].
      const int t = i - kNearData;
      if (t >= 0 && t < nx && last >= t - kNearData) rows[r.at(t, j)] = 1;
    }
  }
  for (int i = 0; i < nx; ++i) {
    int last = -1 - 2 * kNearData;
    for (int j = 0; j < ny + kNearData; ++j) {
      if (j < ny && rows[r.at(i, j)]) last = j;
      const int t = j - kNearData;
      if (t >= 0 && t < ny && last >= t - kNearData) out[r.at(i, t)] = 1;
    }
  }
  return out;
}

// The lowest point of every cell (kNoPoint for an empty one); sets g.cell_of.
std::vector<std::uint32_t> lowest_points(const LocalFrame& l, Ground& g) {
  const std::size_t n = l.x.size();
  std::vector<std::uint32_t> lowest(g.cells(), kNoPoint);
  g.cell_of.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = g.dtm.at(g.dtm.ix(l.x[i]), g.dtm.iy(l.y[i]));
    g.cell_of[i] = std::uint32_t(c);
    if (lowest[c] == kNoPoint || l.z[i] < l.z[lowest[c]]) lowest[c] = std::uint32_t(i);
  }
  return lowest;
}

// PCL's progressive morphological filter on the cells' lowest points: the minima it calls ground.
pcl::Indices pmf_ground(const pcl::PointCloud<pcl::PointXYZ>::Ptr& minima, const Params& params) {
  pcl::Indices ground_minima;
  pcl::ProgressiveMorphologicalFilter<pcl::PointXYZ> pmf;
  pmf.setInputCloud(minima);
  pmf.setCellSize(float(params.cell));
  pmf.setMaxWindowSize(int(std::ceil(params.max_window / params.cell)) > 0 ? float(params.max_window) : 1.f);
  // PCL's threshold is slope * (window step in m) * cell + initial distance.
  pmf.setSlope(float(params.terrain_slope / params.cell));
  pmf.setInitialDistance(float(params.initial_distance));
  pmf.setMaxDistance(float(params.max_distance));
  pmf.setBase(2.0f);
  pmf.setExponential(true);
  pmf.extract(ground_minima);
  return ground_minima;
}

// The ground cells (PMF on the cells' lowest points): their lowest z in the DTM, NaN elsewhere.
// DataError when fewer than min_ground_share of the occupied cells are ground.
void ground_cells(const LocalFrame& l, const std::vector<std::uint32_t>& lowest, const Params& params,
                  const std::string& name, Ground& g) {
  const std::size_t cells = g.cells();
  pcl::PointCloud<pcl::PointXYZ>::Ptr minima(new pcl::PointCloud<pcl::PointXYZ>);
  std::vector<std::size_t> minima_cell;
  for (std::size_t c = 0; c < cells; ++c) {
    if (lowest[c] == kNoPoint) continue;
    const std::uint32_t i = lowest[c];
    minima->push_back(pcl::PointXYZ(float(l.x[i]), float(l.y[i]), float(l.z[i])));
    minima_cell.push_back(c);
  }
  const pcl::Indices ground_minima = pmf_ground(minima, params);
  g.dtm.z.assign(cells, std::numeric_limits<double>::quiet_NaN());
  g.is_ground_cell.assign(cells, 0);
  for (const auto m : ground_minima) {
    const std::size_t c = minima_cell[std::size_t(m)];
    g.dtm.z[c] = l.z[lowest[c]];
    g.is_ground_cell[c] = 1;
  }
  g.ground_cells = ground_minima.size();
  const double share = double(ground_minima.size()) / double(std::max<std::size_t>(1, minima->size()));
  if (share < params.min_ground_share) {
    throw DataError(name,
                    "found ground in only " + format_number("%.1f", 100 * share) + "% of the " +
                        std::to_string(minima->size()) + " occupied " + format_number("%g", params.cell) +
                        " m cells (--min-ground-share " + format_number("%g", params.min_ground_share) +
                        "): no terrain to measure heights from (a tile of only vegetation or objects?)");
  }
}

// Refine: mean z of the points near the first surface, in the ground cells; the others filled
// again from them.
void refine_dtm(const LocalFrame& l, const Params& params, Ground& g) {
  const std::size_t cells = g.cells();
  // The residuals against the first surface are averaged, so a point's position inside its
  // cell (on a slope) does not bias the cell-centre value.
  std::vector<double> sum(cells, 0.0);
  std::vector<std::uint32_t> cnt(cells, 0);
  for (std::size_t i = 0; i < l.x.size(); ++i) {
    const std::size_t c = g.cell_of[i];
    if (!g.is_ground_cell[c]) continue;
    const double d = l.z[i] - g.dtm.height(l.x[i], l.y[i]);
    if (std::abs(d) <= params.ground_tolerance) {
      sum[c] += d;
      ++cnt[c];
    }
  }
  for (std::size_t c = 0; c < cells; ++c) {
    g.dtm.z[c] = g.is_ground_cell[c] ? g.dtm.z[c] + (cnt[c] > 0 ? sum[c] / cnt[c] : 0.0)
                                     : std::numeric_limits<double>::quiet_NaN();
  }
  g.filled_cells = fill_holes(g.dtm, g.near_data);
}

}  // namespace

Ground find_ground(const LocalFrame& l, const Params& params, const std::string& name) {
  Ground g;
  g.dtm = dtm_raster(l, params, name);
  const std::vector<std::uint32_t> lowest = lowest_points(l, g);
  ground_cells(l, lowest, params, name, g);
  const double holes = double(g.cells() - g.ground_cells);
  if (holes > kCellsPerPoint * double(l.x.size())) g.near_data = cells_near_data(g.dtm, lowest);
  fill_holes(g.dtm, g.near_data);
  refine_dtm(l, params, g);
  const std::size_t n = l.x.size();
  g.height.resize(n);
  g.classes.assign(n, kClassOther);
  for (std::size_t i = 0; i < n; ++i) {
    g.height[i] = float(l.z[i] - g.dtm.height(l.x[i], l.y[i]));
    if (g.height[i] < params.min_object_height) {
      g.classes[i] = kClassGround;
      ++g.ground_points;
    }
  }
  return g;
}

}  // namespace canopy::detect
