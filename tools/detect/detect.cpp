// detect's face: validate and run, which calls the rooms in order and assembles the Result.
// Rooms (each a function of explicit inputs returning its own result): frame.h (local frame),
// ground.h (DTM, heights), density.h (the density rule), objects.h (clusters and the vehicle
// tests; clustering.h, footprint.h), shape.h (the shape test), candidates.h (frames and crops).
// The candidates' ground truth is candtruth's (tools/candtruth). docs/decisions/detect.md, "Layout".
#include "detect/detect.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

#include "canopy/common/error.h"
#include "canopy/common/units.h"
#include "detect/candidates.h"
#include "detect/density.h"
#include "detect/frame.h"
#include "detect/ground.h"
#include "detect/objects.h"
#include "detect/shape.h"

namespace canopy::detect {
namespace {

using common::DataError;

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

void validate(const Params& p) {
  auto need = [](bool ok, const std::string& what) {
    if (!ok) throw common::UsageError(what);
  };
  need(p.cell > 0 && std::isfinite(p.cell), "--cell must be > 0");
  need(p.max_window > p.cell, "--max-window must be larger than --cell");
  need(p.terrain_slope > 0, "--terrain-slope must be > 0");
  need(p.initial_distance >= 0 && p.max_distance >= p.initial_distance,
       "need 0 <= --initial-distance <= --max-distance");
  need(p.ground_tolerance > 0, "--ground-tolerance must be > 0");
  need(p.voxel >= 1e-3 && p.voxel <= 100, "--voxel must be in [1 mm, 100 m]");
  need(p.min_object_height >= 0, "--min-object-height must be >= 0");
  need(p.min_length >= 0 && p.max_length >= p.min_length, "need 0 <= --min-length <= --max-length");
  need(p.min_width >= 0 && p.max_width >= p.min_width, "need 0 <= --min-width <= --max-width");
  need(p.min_height >= 0 && p.max_height >= p.min_height, "need 0 <= --min-height <= --max-height");
  need(p.max_height > p.min_object_height, "--max-height must exceed --min-object-height");
  need(p.margin >= 0 && p.margin <= kMaxMargin, "--margin must be in [0, " + common::format_length(kMaxMargin) +
                                                    "] (given " + common::format_length(p.margin) + ")");
  need(p.min_points >= 3, "--min-points must be >= 3");
  need(p.min_planarity >= 0 && p.min_planarity <= 1, "--min-planarity must be in [0, 1] (0 = off)");
  need(p.planar_radius >= 2 * 0.1 && std::isfinite(p.planar_radius), "--planar-radius must be >= 0.2 m");
  need(p.planar_ratio > 0 && p.planar_ratio < 1, "planar_ratio must be in (0, 1)");
  need(p.min_planar_area >= 0, "--min-planar-area must be >= 0");
  need(p.row_roof_height > 0 && p.row_roof_height < 3.0, "--row-roof-height must be in (0, 3) m");
  need(p.row_max_height == 0 || (p.row_max_height > p.row_roof_height && std::isfinite(p.row_max_height)),
       "--row-max-height must be 0 (off) or above --row-roof-height");
  need(p.row_tolerance > 0 && std::isfinite(p.row_tolerance), "--row-tolerance must be > 0");
  need(p.row_trim >= 0 && p.row_trim <= 10, "--row-trim must be in [0, 10] (0: off)");
  need(p.merge_gap >= 0 && p.merge_gap <= 5, "--merge-gap must be in [0, 5] voxels");
  need(p.side_gap >= 0 && p.side_gap <= 5, "--side-gap must be in [0, 5] voxels (0: off)");
  need(p.end_gap >= 0 && p.end_gap <= 5, "--end-gap must be in [0, 5] voxels (0: off)");
  need(p.merge_fragments_gap >= 0 && p.merge_fragments_gap <= 10,
       "--merge-fragments-gap must be in [0, 10] m (0: within --merge-gap only)");
  need(p.min_split_share >= 0 && p.min_split_share <= 1, "--min-split-share must be in [0, 1]");
  need(p.min_ground_share > 0 && p.min_ground_share <= 1, "--min-ground-share must be in (0, 1]");
}

Outputs run(const Params& given, const Inputs& inputs) {
  const formats::PointCloud& tile = *inputs.tile;
  const std::string& name = inputs.name;
  validate(given);
  Params params = given;
  tile.require({"x", "y", "z"}, name, "is this a point cloud?");
  const std::size_t n = tile.size();
  if (n == 0) throw DataError(name, "the tile has no points");
  if (n > std::numeric_limits<std::uint32_t>::max() / 2) throw DataError(name, "more than 2^31 points");
  Result r;
  r.stats.points = n;
  const LocalFrame l = local_frame(tile, name);
  r.origin = l.origin;

  // The DTM cell from the density of all points (the ground is not known yet), detect.md §7.
  const double before_ground = occupied_density(l);
  if (params.cell_from_density) params.cell = cell_for_density(before_ground);
  validate(params);  // a ruled cell must still leave the ground filter's windows valid
  auto t0 = std::chrono::steady_clock::now();
  Ground g = find_ground(l, params, name);
  r.stats.cells = g.cells();
  r.stats.ground_cells = g.ground_cells;
  r.stats.filled_cells = g.filled_cells;
  r.stats.ground_points = g.ground_points;
  r.stats.seconds_ground = seconds_since(t0);

  // The density rule (detect.h): the clustering voxel and the shape test from the tile's density.
  r.density = density_rule(tile, l, g.height, params);
  params.voxel = r.density.voxel;
  params.min_planarity = r.density.min_planarity;
  params.split_rows = r.density.split_rows;
  params.row_tolerance = r.density.row_tolerance;

  t0 = std::chrono::steady_clock::now();
  Objects found = find_objects(l, g.height, params, name);
  ShapeTest shaped = shape_test(std::move(found.accepted), l, params);
  r.stats.band_points = found.band_points;
  r.stats.clusters = found.clusters;
  r.stats.splits = found.splits;
  r.stats.row_splits = found.row_splits;
  r.stats.trims = found.trims;
  r.stats.merges = found.merges;
  r.stats.stacked = found.stacked;
  r.stats.fragments = found.fragments;
  r.stats.rejected_small = found.rejected_small;
  r.stats.rejected_large = found.rejected_large;
  r.stats.rejected_canopy = found.rejected_canopy;
  r.stats.rejected_shape = shaped.rejected;
  r.stats.seconds_objects = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  Placed placed = place_candidates(tile, l, g, shaped.kept, params, found.examined, found.trim_rests);
  r.stats.seconds_candidates = seconds_since(t0);

  r.height = std::move(g.height);
  r.classes = std::move(g.classes);
  for (const Object& o : shaped.kept) {
    for (std::uint32_t q : o.points) r.classes[q] = kClassCandidate;
  }
  r.candidates = std::move(placed.candidates);
  return r;
}

}  // namespace canopy::detect
