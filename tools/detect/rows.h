// Rows of parked vehicles (docs/decisions/detect.md §9): at airborne densities the clustering
// voxel (0.4-0.6 m) bridges the 0.4-1 m gaps between cars parked bumper to bumper, nose-in or
// against a wall, and a row of them becomes one 10-20 m object. Their roofs stay apart: the
// object's points in the roof band (row_roof_height to kRowRoofTop above ground) are clustered
// in the top view at a tolerance below the gaps (PCL's EuclideanClusterExtraction), fragments
// of one roof joined while their union still fits one roof, and every point of the object goes
// to the roof nearest it within a vehicle's reach around the roof; the rest (a wall, a hedge
// beside the row) is left over. Two parts a sampling hole apart with nothing lower between them
// are one roof (scan lines over a truck's or a tank's top).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "detect/footprint.h"

namespace canopy::detect {

// Roof band: row_roof_height (Params) to this height above ground (m); above it a crown over
// the row, which would join the roofs.
constexpr double kRowRoofTop = 3.0;
// An object is looked at as a row when its footprint is longer or wider than one vehicle (m).
constexpr double kRowLength = 6.0, kRowWidth = 2.6;
// Fragments of one roof are joined while the union's rectangle is at most this (m).
constexpr double kRowRoofLength = 5.0, kRowRoofWidth = 1.8;
// A part of the roof band that does not fit one roof is clustered again on its points this much
// higher (m), up to kRowRaises times.
constexpr double kRowRaise = 0.15;
constexpr int kRowRaises = 2;
// A roof of a vehicle that parks in a row is at most this long (m); longer roofs (a truck's
// box, a hedge at roof height) do not count toward a split.
constexpr double kRowRoofMax = 6.5;
// A split needs at least this share of the roof band's points in roofs of vehicle length.
constexpr double kRowRoofShare = 0.6;
// Roofs at most kRowHole tolerances apart with no point below the band between them are one
// (a sampling hole, not a gap between vehicles).
constexpr double kRowHole = 2.0;
// Fewest roof-band points of a roof.
constexpr std::size_t kRowRoofPoints = 5;
// A point joins the roof nearest it in the top view when within kRowAssign of it along the
// roof's long axis (a car's bonnet and boot reach 1-2 m beyond its roof) and kRowSide across it
// (the body's sides, not a wall beside the car), or kRowAssign both ways when the roof is less
// than kRowElongated times as long as wide (its axis is not known).
constexpr double kRowAssign = 1.6, kRowSide = 0.6, kRowElongated = 1.3;
// A part of an object trimmed to one roof (split_row's trim_gap) that holds none of the roof's
// points stays with the vehicle when it lies below the roof band, within kRowAssign of the roof
// along the vehicle and this (m) beside it: a bonnet or boot apart from the roof in the top view.
constexpr double kTrimSide = 0.3;
// A row at least this wide (m) is taken for vehicles parked across it (nose-in), one at most
// kRowWidth wide for vehicles along it, when a roof does not say.
constexpr double kRowNoseIn = 3.4;
// A roof's axis within this of the row's (the object's long axis) or of its perpendicular is
// taken as that (rad; 20 degrees).
constexpr double kRowSnap = 20 * 3.14159265358979323846 / 180;

// The roofs' clustering tolerance for a measured density d (points/m²): kRowSpacings point
// spacings (1 / sqrt(d)), within [0.3 m, 0.6 m].
constexpr double kRowSpacings = 1.5;
double row_tolerance_for_density(double d);

struct RowSplit {
  std::vector<std::vector<std::uint32_t>> pieces;  // one per roof, rows of the tile; empty: no split
  std::vector<std::uint32_t> rest;                 // the object's points near no roof
  bool trimmed = false;  // one vehicle's roof: one piece, the rest trimmed off (trim_gap)
};

// The split of an object (`pts`, rows into x, y: local frame, h: height above ground; its
// footprint `row`) into one piece per roof when at least two of its roofs are at most
// kRowRoofMax long and such roofs hold at least kRowRoofShare of the band's points; else no
// pieces (the object stays whole). `tolerance`: row_tolerance_for_density. Roofs under which
// the object rises above `max_height` (m; 0: no such test) are parts of a taller vehicle and do
// not count toward the two (detect.md §11). When the band holds one such roof (and it holds
// kRowRoofShare of the band's points), the object is one vehicle with something beside it: with
// `trim_gap` > 0 (m) its parts in the top view at that gap that hold none of the roof's points
// and reach beyond the roof's reach are trimmed off (`trimmed`, one piece and the rest; none when
// every part is the vehicle's; detect.md §12).
RowSplit split_row(const std::vector<std::uint32_t>& pts, const std::vector<double>& x,
                   const std::vector<double>& y, const std::vector<float>& h, const Footprint& row,
                   double roof_height, double tolerance, double max_height, double trim_gap);

}  // namespace canopy::detect
