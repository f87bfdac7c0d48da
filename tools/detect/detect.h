// detect: vehicle candidates in a whole tile (issue 14).
//
// 1. Local frame. The tile's coordinates (float64, possibly UTM magnitudes) are shifted by an
//    integer-metre origin (the bounding-box centre, lowest z) so every float32 PCL computation
//    works on small numbers; the origin goes back into every transform in float64.
// 2. Ground (DTM). The lowest point of every `cell` × `cell` column forms a minimum-elevation
//    raster; PCL's ProgressiveMorphologicalFilter classifies those minima as ground or not
//    (Zhang et al. 2003, run on the raster as in the paper); empty and non-ground cells are
//    filled from their ground neighbours (breadth-first, mean of the filled 8-neighbours);
//    the ground cells are then refined to the mean z of the points within `ground_tolerance`
//    of the first surface (the minimum is biased low by noise). Height above ground of every
//    point = z − bilinear DTM.
// 3. Objects. Points between `min_object_height` and `max_height` above ground (not ground or
//    grass, not canopy above the tallest vehicle) are clustered: occupied `voxel` cubes,
//    26-connected (or PCL's Euclidean clustering on the voxel centres, same partition).
// 4. Vehicle test. A cluster reaching the band's top under points just above the band is the
//    bottom of a crown or building, not a vehicle. Per cluster the minimum-area rectangle of its top view
//    (length ≥ width, heading of the long axis) and its height. A cluster wider than two narrow vehicles, or
//    beyond the ranges, is re-clustered with half the voxel (objects that only touch come
//    apart: two vehicles side by side, a vehicle against a bush); an oversized one that does
//    not come apart is cut at a clear valley of the point count across its oversized axis,
//    or kept when at most 25% beyond the ranges (recall first), else rejected. Below
//    kRowSplitDensity a cluster longer or wider than one vehicle is first split into one piece
//    per roof where its points 1.1-3 m above ground cluster apart (rows of parked vehicles,
//    rows.h, `split_rows`); a cluster of one such roof that would be accepted whole keeps
//    only its parts in the top view that hold the roof or a bonnet beside it (`row_trim`).
//    A half-voxel split is kept only when its parts hold `min_split_share` of the points
//    (and, for an object only wider than two narrow vehicles, lie side by side); accepted
//    objects touching end to end in the top view whose union fits one vehicle are merged
//    (`merge_gap`: a tractor unit's cab and deck; detect.md §10); before any of this, clusters
//    that touch in the top view beside each other, in line, are joined (`join_stacked`: a
//    vehicle's parts at two heights seen from above, detect.md §16). An accepted cluster whose
//    surface is mostly not planar and holds little planar area (bush groups, crown pieces:
//    leaves are volumetric scatter, a vehicle is made of panels) is rejected
//    (`min_planarity`, `min_planar_area`).
// 5. Candidates. Per accepted cluster: a rigid local frame (origin on the DTM at the
//    footprint centre, z = the normal of the ground plane fitted under the footprint, x = the
//    long axis); every input point inside the footprint + `margin` and below height + margin,
//    in that frame, with all its fields (sensor/normal directions rotated).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"

namespace canopy::detect {

enum class Clustering { kGrid, kEuclidean };

// The largest --margin: a crop serves one candidate's fits, and each crop's points grow with
// the margin squared (docs/decisions/hardening.md, stop 71).
inline constexpr double kMaxMargin = 10.0;

struct Params {
  // Ground.
  double cell = 0.5;              // DTM cell (m), > 0
  double max_window = 16.0;       // largest PMF window (m): objects narrower than this are not ground
  double terrain_slope = 0.35;    // PMF threshold growth per metre of window (rise / run), > 0
  double initial_distance = 0.2;  // PMF height threshold at the smallest window (m)
  double max_distance = 3.0;      // PMF height threshold cap (m)
  double ground_tolerance = 0.2;  // |height| within which a point refines the DTM (m)
  double min_ground_share = 0.2;  // fewer occupied cells with ground: no terrain, an error
  // Objects.
  double min_object_height = 0.3;  // below this height above ground: ground or grass (m)
  double voxel = 0.2;              // clustering voxel edge (m); see voxel_from_density
  Clustering clustering = Clustering::kGrid;
  // Vehicle ranges (a 3 m car to a 16 m tractor with trailer, partly hidden).
  double min_length = 2.0, max_length = 17.0;
  double min_width = 1.0, max_width = 4.0;  // the tank is 3.54 m over its tracks
  double min_height = 0.8, max_height = 4.5;
  std::size_t min_points = 30;  // fewer points in a cluster: not a candidate
  // Shape (docs/decisions/detect.md): the share of the object's 0.1 m voxel centroids whose
  // neighbours within planar_radius are planar (sqrt(l3 / l2) <= planar_ratio of their
  // covariance's eigenvalues), and their area. An object with a share below min_planarity
  // and a planar area below min_planar_area is vegetation (bush groups, crown pieces).
  double min_planarity = 0.2;    // 0 = no shape test
  double min_planar_area = 1.0;  // m^2 of planar surface that keep an object whatever its share
  double planar_radius = 0.35;   // neighbourhood radius (m)
  double planar_ratio = 0.35;    // largest sqrt(l3 / l2) of a planar neighbourhood
  // The density rule (docs/decisions/detect.md §7): with these set, `voxel` and
  // `min_planarity` are not used as given but set from the tile's measured density d (open
  // ground's points per m², else all points per occupied m²): voxel = max(0.2 m, 1.9 / sqrt(d))
  // (a sparse vehicle stays one object), and the shape test (min_planarity 0.2) only where
  // d >= kPlanarityDensity (below it every object scores planarity 0: detect.md §3b). At the
  // dense end (d >= 90.25) both are the fixed values above. An explicit option clears them.
  bool voxel_from_density = true;
  bool cell_from_density = true;  // DTM cell from the density rule (cell_for_density) unless --cell is given
  bool planarity_from_density = true;
  // Rows of parked vehicles (detect.md §9, rows.h): an object longer or wider than one vehicle
  // is split into one piece per roof where the points of its roof band (row_roof_height to
  // 3 m above ground) cluster apart at row_tolerance in the top view. With
  // split_rows_from_density the rule sets split_rows (on where d < kRowSplitDensity); an
  // explicit --split-rows clears it. run() sets row_tolerance from the density
  // (row_tolerance_for_density, rows.h) whatever the option.
  bool split_rows = false;
  bool split_rows_from_density = true;
  double row_roof_height = 1.1;  // bottom of the roof band (m above ground)
  // The tallest vehicle that parks in a row (cars, vans): a roof-band part under which the
  // object rises higher is a slice of a taller vehicle (a tractor unit's cab, a wheel loader),
  // not a roof, and a split needs two roofs (detect.md §11); 0 = no such test (the rule before).
  double row_max_height = 3.0;
  double row_tolerance = 0.45;  // roofs' clustering tolerance in the top view (m)
  // An object accepted whole whose roof band holds one such roof (one vehicle with something
  // lower joined to it by the voxel: a bicycle stand, a planter, a low hedge) keeps only its
  // parts in the top view, at row_trim x row_tolerance apart, that hold the roof or lie below
  // the band within its reach (a bonnet); the other parts are objects of their own (detect.md
  // §12); 0 = no trim (the rule before).
  double row_trim = 1.0;
  // An object re-clustered at half the voxel (touching objects) is split only when the parts
  // it keeps hold at least this share of its points (detect.md §10); 0 = any two parts (the
  // rule before).
  double min_split_share = 0.8;
  // Accepted objects whose points come within merge_gap clustering voxels of each other in the
  // top view, end to end, and whose union fits one vehicle are merged (the cab and the deck of
  // a tractor unit; detect.md §10); 0 = no merging (the rule before).
  double merge_gap = 0.5;
  // An object only wider than two narrow vehicles is cut across its width at an empty slab only
  // when the run of empty 0.05-0.2 m slabs is at least this many clustering voxels wide (half a
  // voxel = one point spacing under the density rule): narrower runs are the spaces between the
  // scan lines over one wide body's top (a tank aligned with the scan lines), not a gap between
  // two vehicles side by side (detect.md §14); 0 = any empty slab, the rule before and the
  // default: 0.5 kept a tank whole but added a false alarm on forest_bcts_1 (not adopted).
  double side_gap = 0.0;
  // An object that would be accepted whole is cut across its long axis at a run of empty slabs
  // at least this many clustering voxels long in which the ground is seen (a tile point under
  // min_object_height between the object's sides): two bodies end to end that the voxel joined
  // (a vehicle and a bush at its end), not a sampling hole over one body's top, which hides the
  // ground under it (detect.md §19); 0 = no such cut, the rule before and the default.
  double end_gap = 0.0;
  // Pieces of a row split are never merged (the row rule decided them), except with a piece
  // that rises above row_max_height: the row rule does not decide for taller vehicles (§11), and
  // a tractor unit's cab cut from its deck by a row split is merged back (detect.md §13);
  // false = row pieces never merged (the rule before).
  bool merge_tall_rows = true;
  // Clusters that touch in the top view, beside each other (not one over the other), whose
  // union is in line and fits one vehicle are one object before any split: a vehicle's parts at
  // different heights whose vertical faces the sensor did not see (a cab beside a deck seen
  // from above; detect.md §16); false = the rule before.
  bool join_stacked = true;
  // A cluster of the clustering too small to be an object (fewer than min_points, or shorter,
  // narrower or lower than the vehicle ranges) that lies under a crown (most of its points have a
  // tile point over them, higher than the object's top by a clustering voxel) is part of the
  // accepted object it touches in the top view (within merge_gap voxels) when their union stays in
  // line (no wider than the object + 0.3 m) and fits the vehicle ranges: the part of a vehicle
  // hidden under a crown returns few, sparse points, which the voxel leaves unconnected to the
  // rest (detect.md §24); false = such fragments dropped, the rule before and the default.
  bool merge_fragments = false;
  // With merge_fragments: a fragment farther than merge_gap voxels from the object, but at most
  // this far (m), is merged when the gap between them is hidden: a crown over all of it and no
  // ground seen in it (between two parts of one vehicle its body hides the ground); 0 = only
  // fragments within merge_gap (detect.md §24).
  double merge_fragments_gap = 0.0;
  // With merge_fragments: only a fragment beside the object (at most a quarter of its top-view
  // cells also hold the object's points, join_stacked's test), not over it (detect.md §24).
  bool merge_fragments_beside = false;
  // Candidates.
  double margin = 0.5;  // crop margin around the footprint and above the height (m)
  // Each crop gets the field `object` (uint8, kObjectField): 1 for the points of the candidate's
  // own object (its cluster after every split, trim and merge), 2 for points detect gave to
  // something else (another object or piece), 3 for those of them that a trim to one roof cut
  // off this object (its leftover, detect.md §12, §18), 0 for the rest of the crop (ground,
  // grass, points dropped from its own cluster), for inspection (classify's readers of it were
  // removed, classify.md §40; detect.md §17, §18); false = no such field, the crops before, and
  // detect keeps no record of its examinations.
  bool object_field = false;
};

// Throws common::UsageError naming the option (--cell, ...) of the first bad value: cell > 0,
// max_window > cell, terrain_slope > 0, 0 <= initial_distance <= max_distance,
// ground_tolerance > 0, voxel in [1 mm, 100 m], min_object_height >= 0, 0 <= min <= max of length, width and
// height, max_height > min_object_height, margin >= 0, min_points >= 3, min_planarity in
// [0, 1], planar_radius >= 0.2 m, planar_ratio in (0, 1), min_planar_area >= 0,
// min_ground_share in (0, 1], min_split_share in [0, 1], merge_gap in [0, 5], row_trim in [0, 10], end_gap in [0, 5].
void validate(const Params& params);

// The tile's ground-truth fields (rangetrace's tiles): never copied into a crop, so no later
// stage can read them by accident (issue 30); candtruth reads them from the tile.
inline const char* const kTruthFields[] = {"label", "instance"};
// The crop's field marking the candidate's own object (Params::object_field): 1 its points, 2
// points detect gave to something else (another object, a piece a row split or trim cut off,
// accepted or not), 3 of those the points a trim to one roof cut off this object (the trim's
// leftover: the low thing beside the vehicle, whatever became of it), 0 the rest (ground, grass,
// points above the band, what detect dropped from this object's own cluster).
inline const char* const kObjectField = "object";
constexpr std::uint8_t kObjectContext = 0, kObjectOwn = 1, kObjectOther = 2, kObjectTrimmed = 3;

// Classes of the classification output.
enum Class : std::uint8_t { kClassGround = 1, kClassOther = 2, kClassCandidate = 3 };

// The shape test needs about 21 returns per m² of surface (detect.md §3b); at least this
// measured density switches it on under the density rule (detect.md §7).
constexpr double kPlanarityDensity = 30;
constexpr double kDenseVoxel = 0.2;         // the voxel at the dense end (m)
constexpr double kVoxelDensityScale = 1.9;  // voxel = max(kDenseVoxel, scale / sqrt(density))
constexpr double kDensePlanarity = 0.2;     // min_planarity at the dense end
// The DTM cell holds about kCellReturns returns of all kinds at the tile's density: under a
// closed canopy that lets 5-10 % of the returns reach the ground, a cell still expects one or
// two ground returns (detect.md §7). cell = clamp(sqrt(kCellReturns / density), 0.5 m, 2 m).
constexpr double kCellReturns = 24;
constexpr double kDenseCell = 0.5;   // the DTM cell at the dense end (m), today's default
constexpr double kSparseCell = 2.0;  // coarsest DTM cell the rule picks (m)
// Rows of parked vehicles are split below this measured density (detect.md §9): where the rule's
// voxel exceeds the dense 0.2 m (d < (1.9 / 0.2)^2), i.e. airborne surveys, never the dense
// simulated tiles, whose 0.2 m voxels already keep 0.4 m gaps apart.
constexpr double kRowSplitDensity = 90.25;

// The tile's density, measured on 1 m cells of the local frame (x, y).
struct Density {
  double all = 0;                // points per occupied 1 m cell (per m²)
  std::optional<double> ground;  // points per m² on open ground cells (every point below min_object_height)
  std::optional<double> first;   // first returns per occupied m², when return_number is known
  std::size_t occupied_cells = 0, open_cells = 0;
  double rule = 0;                      // what the density rule used: ground, else all
  double voxel = 0, min_planarity = 0;  // the values detect applied
  bool voxel_by_rule = false, planarity_by_rule = false;
  double cell = 0;  // the DTM cell detect applied (m)
  bool cell_by_rule = false;
  bool split_rows = false, split_rows_by_rule = false;  // rows split (detect.md §9)
  double row_tolerance = 0;                             // the roofs' tolerance applied (m)
};

// The density rule's values for a measured density d (> 0).
double voxel_for_density(double d);
double planarity_for_density(double d);
double cell_for_density(double d);

struct Candidate {
  std::string id;                                         // "c0001", ...; also the PCD's file stem
  Eigen::Matrix4d to_tile = Eigen::Matrix4d::Identity();  // local -> tile coordinates (float64)
  double length = 0, width = 0;                           // footprint (m), length >= width
  double heading = 0;  // local x axis in the tile's xy plane, from +x toward +y (rad, (-pi/2, pi/2])
  double height = 0;   // highest object point above the ground (m)
  std::size_t object_points = 0;  // points of the cluster
  double density = 0;             // object_points / (length x width), per m²
  double planarity = 0;           // share of the object's surface in planar neighbourhoods
  double planar_area = 0;         // that planar surface (m^2)
  formats::PointCloud cloud;      // the crop, local frame, every input field but the truth (kTruthFields)
};

struct Stats {
  std::size_t points = 0, ground_cells = 0, filled_cells = 0, cells = 0;
  std::size_t ground_points = 0, band_points = 0, clusters = 0, splits = 0, row_splits = 0, trims = 0,
              merges = 0, stacked = 0, fragments = 0;
  std::size_t rejected_small = 0, rejected_large = 0, rejected_canopy = 0, rejected_shape = 0;
  double seconds_ground = 0, seconds_objects = 0, seconds_candidates = 0;
};

struct Result {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // local frame origin in tile coordinates
  std::vector<float> height;                         // per input point: height above the DTM (m)
  std::vector<std::uint8_t> classes;                 // per input point: Class
  std::vector<Candidate> candidates;                 // sorted by footprint centre (x, then y)
  Stats stats;
  Density density;
  // The tile's CRS as its file records it ("EPSG:<code>": formats::las_crs of the header block
  // read_points hands back) and where it was read, for the index's "crs" and "crs_from"; "" =
  // none. run() leaves them empty (the detection does not use them): the caller sets them.
  std::string crs, crs_from;
  // What detect warned about the tile as it read it (the index's "warnings": feet, a CRS record
  // without an EPSG code, the trajectory's gaps), for collect to relay; run() leaves it empty,
  // the caller sets it.
  std::vector<std::string> warnings;
};

struct Inputs {
  const formats::PointCloud* tile = nullptr;
  std::string name;
};

using Outputs = Result;

// Input: x y z (any type; float64 keeps UTM magnitudes), any other fields. `name` names the
// tile in errors. Throws common::DataError for a tile it cannot work on (no points,
// non-finite coordinates, float32 coordinates too large to be exact, an extent too large for
// the DTM: over 2e7 cells, or over 4e6 + 16 per point (a few points spread wide), an object
// band wider than 2^21 - 2 voxels, no ground found). A tile with no vehicle gives zero
// candidates. The DTM's hole relaxation works only within 2 cells of a cell holding a point.
Outputs run(const Params& params, const Inputs& inputs);

// The classification point set: x y z (float32, local frame = tile − origin), height,
// class, red green blue (ground brown, vegetation/other green, candidate red).
formats::PointCloud classification_cloud(const formats::PointCloud& tile, const Result& result);

}  // namespace canopy::detect
