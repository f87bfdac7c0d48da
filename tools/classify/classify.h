// classify: a class-level answer for one detect candidate (issue 27, "Answers at the level the
// data supports"; docs/decisions/classify.md). At airborne-survey densities (10-30 points/m²: a
// car returns 60-150 points) the model-level chain (fitvox | cocone | ncut | gmatch | verify)
// has too few points per voxel; what the points do support is "vehicle, car-sized, heading
// 37°". classify answers that, or `none` with a reason, from the candidate's points alone:
//
// 1. Object. The candidate PCD (detect's crop: local frame, ground z = 0, x along the
//    footprint's long axis) is split into ground (z < ground_cut) and above-ground points; the
//    above-ground points are clustered (single linkage at a distance scaled to the crop's point
//    spacing, heights counting a third) and the cluster under the frame's origin (detect's
//    object centre) is the object.
// 2. Rectangle. Minimum-area rectangle of the object's top view (convex hull, one side on a
//    hull edge); its long axis is the heading, with a 180° ambiguity.
// 3. Size. Measured L, W (the rectangle) and H (a high quantile of the heights), with a
//    sampling correction: a surface sampled with spacing s loses about s/2 at each edge, so
//    L += edge_factor * s, W += edge_factor * s, s = 1 / sqrt(density), density = object
//    points per m² of the rectangle (docs/decisions/classify.md §3 measures the factor).
// 4. Shape cues that work on few points: the top's height profile along the long axis (the
//    share of it within a drop of the top: a car's roof plateau, a van's long roof, a
//    container's flat box; the levels of its ends), the local roughness of the top, points
//    under other points and ground returns under the object inside the footprint (a crown lets
//    pulses through, a roof does not), the object's density against the open ground's (fill),
//    and, when the file has return numbers, the share of later returns.
// 5. Decision. too_sparse (points, density) -> vegetation_like (cues) -> size gates against the
//    families' class ranges (tools/rangetrace/families.cpp; docs/decisions/families.md §2):
//    too_large / too_small / too_flat / not_vehicle_shape -> the class whose ranges the size
//    fits best (profile cues break ties between overlapping classes) and its group -> the
//    outline gates (docs/decisions/classify.md §16): an answer with a drawbar end, or a tracked,
//    van or bus answer with too deep a step in its profile, is not_vehicle_shape; with
//    --min-rectangularity (off by default, §17) so is a car answer with an oval outline.
//
// Never read: `classification` (ASPRS classes), `label`, `instance` (truth). Only x y z,
// return_number, number_of_returns, point_source_id and gps_time are read.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "canopy/common/density_scale.h"
#include "canopy/documents/candidates.h"
#include "canopy/formats/point_cloud.h"
#include "canopy/formats/provenance.h"

namespace canopy::classify {

// One procedural family's dimension ranges (m; families.md §2) and its coarse group.
struct ClassRange {
  std::string name;
  std::string group;
  std::array<double, 2> length, width, height;
  // What the top's profile should show (families.md §3): +1 / -1 = the plateau covers most /
  // a minor part of the length (box-truck, bus, van / wheel-loader, semi-tractor), the higher
  // end stays up at the roof / drops to a bonnet, boot or bed at both ends (hatchback, suv,
  // van / sedan, pickup); 0 = no expectation.
  int plateau = 0, tail = 0;
  bool flat_box = false;  // its top may be one flat box over the whole length (box-truck, bus)
  std::array<double, 2> hull_length{0, 0};  // tank: the hull without the gun (families.md §2), or 0 0
};
// A range of the class table: a family's, or a modelbase entry's (`entry`: its name).
struct TableRange : ClassRange {
  std::string entry;
  bool open_end = false;  // an entry whose own surface has an open end (end_fill < min_end_fill)
  // An entry's own top profile, measured on its surface as on a candidate: plateau share, lower
  // and higher end level (share of H); none for a family or an unmeasured entry.
  std::optional<std::array<double, 3>> profile;
  // A class's envelope (--class-envelope): the number of its entries it spans (0: not one), and
  // their measured profiles (the envelope stands for a top within entry_profile of any of them).
  std::size_t envelope = 0;
  std::vector<std::array<double, 3>> profiles;
};

// The twelve families, in families.cpp's order, with their groups:
// car = sedan, hatchback, suv, pickup; van = van; truck = box-truck, semi-tractor; bus = bus;
// tracked = tracked-apc, tank; machine = wheel-loader, wheeled-apc.
const std::vector<ClassRange>& class_ranges();

struct Params {
  double ground_cut = 0.3;   // points below this height are ground or grass (m; detect's band)
  double link_factor = 2.5;  // object clustering: linking distance = factor x the crop's spacing
  // Gap bridging (classify.md §21; 0 = off): after the clustering, a cluster in line with the
  // object along the candidate frame's x axis (detect's long axis: within the object's extent
  // across it + the link), no higher than the object's top and reaching at least half of it,
  // whose nearest point is at most `bridge` from the object's in the top view and with (almost) no
  // ground returns between them, joins it while the joined length stays at most `bridge_length`
  // (a windscreen or rear window that returned nothing, not even the ground under it, splits a
  // car into cabin, bonnet and boot once the link is shorter than the glass).
  double bridge = 0;
  double bridge_length = 6.0;
  // What --bridge crossed (classify.md §27). bridge_fill true: `fill` counts the object's points on
  // its rectangle less the strips the bridge crossed, each by the share of it that returned nothing
  // (not even the ground: a vehicle's glass; a crown lets the ground through); false: on the whole
  // rectangle (before). bridge_min_share > 0: a cluster joins only when it holds at least this share
  // of the object's points (a bonnet, not a few stray returns in line with the car; 0: any, before).
  // Off here, in classify.ini and classify-sim.ini; the rule measured in §27: bridge 1 m,
  // bridge_fill true, min share 0.1.
  bool bridge_fill = false;
  double bridge_min_share = 0;
  // fill_empty_cells true (classify.md §27): `fill` leaves out of any object's rectangle the cells
  // (2 x the crop's spacing; at least that, fitted to the rectangle) that hold no return at all,
  // neither the object's nor the ground's nor any other (glass, dark paint; a crown's gaps return
  // the ground); it replaces bridge_fill's strips. false: as bridge_fill says (before).
  bool fill_empty_cells = false;
  // fill_tile_ground true (classify.md §31): when the crop leaves `fill` unmeasured (under 10 ground
  // returns or 1 m² of it outside the rectangle: a candidate under closed canopy or in a crowd),
  // `fill` is measured against the tile's open-ground density instead (detect's index
  // density.ground: points per 1 m cell holding only ground; Candidate::tile_ground_density).
  // false: unmeasured, the cue passes (before).
  bool fill_tile_ground = false;
  // fill_tile_first true (classify.md §46): with fill_tile_ground, where the tile has no open-ground
  // density either (density.ground null: a plot under closed canopy), `fill` is measured against
  // the tile's first-return density (density.first: one first return per pulse, as open ground
  // returns one per pulse). false, or fill_tile_ground false: unmeasured there (before).
  bool fill_tile_first = false;
  // Parts stacked in height (classify.md §25): seen from above a vertical face returns nothing,
  // so a semi-tractor's cab (3.6 m) and its deck (1.2 m), an earthmover's cab top and its body are
  // clusters that touch only in the top view (a step of more than 3 links). true: a cluster that
  // meets the object within the link in plan, lies beside it (at most 25% of the smaller one's
  // top-view cells shared), in line with it (the union at most 0.3 m wider across the
  // candidate's long axis) and is a part (at least 10% of the object's points) joins it, as
  // detect's --join-stacked joins clusters (detect.md §16).
  // false: the object is one cluster (before; Params and classify.ini).
  bool join_stacked = false;
  // Echo widths (classify.md §25): the realistic sensor records each echo's width; a level hard
  // surface returns the pulse's own width, foliage spread in range inside the footprint a wider
  // one. With echo widths in the candidate and this > 0: an object whose median echo is more than
  // this many times the open ground's single returns' is vegetation_like; one at or under it is
  // hard, and ground_through does not refuse it (the ground under a hard top is seen beside its
  // parts' edges, not through it; with echo_late, late_returns does not either: a hard top under a
  // crown returns late because the crown took the pulse first). 0: off (before; Params and
  // classify.ini: the real tiles carry no echo widths).
  double max_echo_widening = 0;
  bool echo_late = false;
  // With echo_late, a hard object whose late_returns exceeds max_late_returns (the cue waived: under
  // a crown) is held to the drawbar gate at this end width (share of W) instead of drawbar_width
  // when it is larger (classify.md §44): with the late cue gone, the outline is all that stands
  // between a vehicle and a trailer under a crown, and a drawbar seen from above through a crown
  // measures wider than in the open. 0: drawbar_width as for any object (Params, classify.ini).
  double echo_late_drawbar = 0;
  // With echo_late, late_returns is waived only for an object whose echo_widening is at most this
  // (classify.md §44: the whole vehicles' largest on the sensor ladder was 1.008, pipes and logs
  // under crowns 1.01-1.03): a late-dominated object must be hard beyond doubt. 0: every hard
  // object (max_echo_widening), as before.
  double echo_late_widening = 0;
  double link_min = 0.25;       // object clustering: the linking distance is at least this (m)
  std::size_t min_points = 20;  // fewer object points: too_sparse
  double min_density = common::kClassLevelDensity;  // fewer points per m² of its rectangle: too_sparse
  double edge_factor = 0.15;                        // sampling correction: L, W += edge_factor x spacing
  double height_quantile = 0.98;                    // H = this quantile of the object's heights
  // Size gates: a measured dimension may miss a class range by gate x its uncertainty
  // sqrt(size_sigma² + (spacing_sigma x spacing)²).
  double size_sigma = 0.15;
  double spacing_sigma = 0.5;
  double size_gate = 2.5;
  // Shape cues: fitted on real development tiles (share/params/classify.ini, classify.md §5;
  // the simulated fit: classify-sim.ini).
  double plateau_drop = 0.2;  // profile bins within this of the top (+ 10% of H) are plateau (m)
  // Which roughness the threshold reads (classify.md §19): kPlane (default; classify.ini and
  // classify-sim.ini) a cell's top against the plane of its 3 x 3 cells' tops; kLine against its
  // nearest occupied neighbours on the straightest of four lines through it (a vehicle's top is
  // smooth along at least one direction), with max_roughness 0.20: on the real development tile
  // it kept two more clear cars, on the held-out real tiles it let 13 more non-vehicles through
  // (precision 78.9% -> 62.7%), so it is an option, not the default (§19, "held-out").
  enum class Roughness { kPlane, kLine };
  Roughness roughness = Roughness::kPlane;
  double max_roughness = 0.45;   // rougher top (median local residual) than this x the spacing,
                                 // and than roughness_floor: vegetation_like (0.20 for kLine, §19)
  double roughness_floor = 0.1;  // the threshold's floor (m; §5). The cells' own floor (0.3 m =
                                 // 1.5 spacings) gives max_roughness x 0.2 m (0.13 m at 0.65; §28)
  // Equipment on a top (classify.md §43): with kPlane, a top over the plane's threshold is refused
  // only when it is rough along lines too, its line roughness (top_roughness_line) over
  // max_roughness_line x max(the spacing, 0.2 m) (the cells' own floor, 0.3 m = 1.5 x 0.2 m; no
  // roughness_floor: a sampled panel is smooth along lines): a ladder, a rack or boxes on a roof
  // put cells at two levels, which no plane fits, but each part runs on along some line; a
  // crown is rough along every line. 0: off (the plane alone, as before).
  double max_roughness_line = 0;
  double max_below_share = 0.25;    // more interior object points under another one: vegetation_like
  double max_ground_through = 0.2;  // more interior ground returns under the object: vegetation_like
  double min_fill = 0.55;           // fewer points per m² of its rectangle than this x the open
                                    // ground's around it (a porous or patchy object): vegetation_like
  double max_late_returns = 0.4;    // more object points with return_number > 1: vegetation_like
  double min_plateau = 0.45;        // less of its length within plateau_drop of the top (no roof):
                                    // not_vehicle_shape (0: off; real tiles, §5)
  double min_end_fill = 0;          // end_fill below this: not_vehicle_shape, unless the class is a
                                    // tank (a gun over its end); 0: off (classify.md §15)
  // Outline gates (classify.md §16; each 0: off). A car-group answer needs a notch (bonnet or
  // boot under the cabin: the profile's depth under its upper hull, share of H) of at least
  // min_notch; a tracked, van or bus answer at most max_notch; any answer whose narrower end is
  // narrower than drawbar_width x W and lower than drawbar_level x H (a trailer's or caravan's
  // drawbar) is refused. All: not_vehicle_shape.
  double min_notch = 0;  // off: modern cars' profiles are convex too (classify.md §16)
  double max_notch = 0.5;
  double drawbar_width = 0.3;
  double drawbar_level = 0.4;
  // A car-group answer whose top view's convex hull fills less than min_rectangularity of its
  // minimum-area rectangle (an oval outline: a rock) and whose notch is under
  // rectangularity_notch (no bonnet or boot step: real cars are oval from above too, but
  // stepped) is not_vehicle_shape (classify.md §17; min_rectangularity 0: off; notch 1: the
  // outline alone).
  double min_rectangularity = 0;
  double rectangularity_notch = 0.08;
  // The rectangularity gate weighs Features::notch_sampled instead of notch: a step only where the
  // lower bin is sampled like the profile's others (classify.md §37; false: notch, before).
  bool rectangularity_sampled = false;
  // A car- or van-group answer whose shoulder (Features::shoulder) is under min_shoulder (a body
  // that narrows upward: a log or pipe stack, a ridge or dome tent) is not_vehicle_shape
  // (classify.md §30; 0: off).
  double min_shoulder = 0;
  // A car- or van-group answer whose rim (Features::rim) is over max_rim (an open top: a flatbed's
  // side boards, an open box's walls above its floor; a car's or van's roof is highest across its
  // middle) is not_vehicle_shape (classify.md §38; 0: off, before; Params and classify.ini).
  double max_rim = 0;
  // A top whose bed (Features::bed) is at least min_bed (an open bed behind a cab) is no car- or
  // van-group class but a pickup: those classes are left out of its choice, as a flat box leaves
  // all but the box-truck and the bus (classify.md §39; 0: off, before).
  double min_bed = 0;
  double plateau_split = 0.6;    // plateau share between a minor and a long plateau
  double tail_split = 0.75;      // higher end's level (share of H) between dropping and staying up
  double profile_penalty = 1.5;  // added to a class's size distance when the profile contradicts it
  double box_plateau = 0.88;     // plateau share and both ends' levels at or above this:
  double box_ends = 0.8;         //   a flat box (container, log stack): a box-truck or bus only
  double model_density = common::kModelLevelDensity;  // points/m² the model-level chain needs
  // Cues over the passes that saw the object (classify.md §14): when the crop holds points of
  // several flight passes (LAS point_source_id / gps_time), the open ground of `fill` and the
  // ground returns of `ground_through` count only the passes that hold >= pass_share of the
  // object's points (a parked car gone, or not yet there, when another line flew over leaves
  // that line's ground under and around it). false: every pass (before).
  bool by_pass = true;
  double pass_share = 0.1;
  // Sight lines (classify.md §20): a point counted by below_share or ground_through counts only
  // when the line from it toward the sensor that saw it (the candidate's sensor_x/y/z) passes
  // through the object above it: an object point within half the spacing of the line, or object
  // points around the line (no gap of half a turn) within 1.5 spacings at some height. A crown's
  // deep return was seen through its foliage; a point under a solid part's overhang (a hood
  // under a cab roof's edge, a fender beside a hood, a frame under lift arms, a bucket's floor
  // inside its walls, the ground beside a tyre) was seen past that part's edge. Points without a
  // sensor direction count as before. false: every point counts (before; Params and
  // classify.ini; classify-sim.ini true).
  bool sight_lines = false;
  // Late returns inside the object (classify.md §22): late_returns counts a later return
  // (return_number > 1) only when every earlier return of its pulse (same point_source_id,
  // gps_time and number_of_returns) is in the candidate's crop at or below the object's top: the
  // pulse was split inside the object (a crown's own depth). A later return whose pulse met
  // something first above the object's top, or outside the crop (a crown over a car: the crop
  // ends 0.5 m over the object), is not evidence of porosity. Points without gps_time count as
  // before. false: every return_number > 1 counts (before).
  bool late_returns_inside = false;
  // Late returns weighed by the shade around the object (classify.md §26): a later return whose
  // pulse met something first above the object's top or outside the crop (shadowed, §22) counts
  // for late_returns by the share of the crop's ground returns around the object (outside its
  // rectangle) that are later returns themselves: a layer that shades the object and its
  // surroundings alike (a closed stand) leaves the returns their full weight; one that shades the
  // object but not the open ground beside it (a single crown over a car) takes it away. A return
  // split inside the object counts 1; without gps_time, or with fewer than 10 ground returns of
  // known return number around the object, every later return counts 1 (before). false: every
  // return_number > 1 counts (before; Params, classify.ini and classify-sim.ini).
  bool late_shadow = false;
  // Edge splits under the object (classify.md §23): ground_through does not count a ground
  // return that is a later return of a pulse whose every earlier return (same point_source_id,
  // gps_time and number_of_returns; returns 1 .. k - 1 all present) is an object point on the
  // edge of the object's solid layer (the object points that ended their pulse: within
  // max(0.5 m, 2.5 spacings) horizontally and 0.25 m vertically of it they are fewer than 3 or
  // leave an angular gap of 3/8 of a turn or more): a beam whose footprint straddles a roof's
  // edge, a window's frame or a cab's step splits into an edge return and a ground return on one
  // axis. Points without gps_time count as before. false: every ground return counts (before;
  // Params, classify.ini and classify-sim.ini: on the sensor tiles a bush's sparse layer is all
  // edge, and its ground returns were set aside too).
  bool ground_through_edges = false;
  // Modelbase entries with a class (--modelbase) are classes too: each entry's L W H widened by
  // this share either way is one more class range, of the entry's class (classify.md §12).
  bool entry_classes = true;
  double entry_tolerance = 0.05;
  // An entry's range stands for its model (classify.md §18): it is no class for a candidate whose
  // top's profile (plateau share, lower and higher end level) differs from the entry's own by
  // more than this (absolute share, any of the three; a jeep's bonnet against a van's long roof).
  // 0: off (before; Params and classify.ini; classify-sim.ini 0.2).
  double entry_profile = 0;
  // Only the modelbase's classes (docs/decisions/open-set.md, fourth round): when entries with a
  // class are given, a family is a class range only if its name or its group is one of their
  // classes (a modelbase of cars, vans and trucks is never answered wheel-loader). false: every
  // family (before).
  bool modelbase_classes_only = false;
  // With modelbase_classes_only, a family is a class range only when at least this many entries
  // name it (its name or its group; docs/decisions/open-set.md, eleventh round): a class the
  // modelbase shows by one instance is that entry's range (and profile), not its family's whole
  // range (the tracked-apc family's 2.70 m width floor and 1.90 m height held a 2.6 m wide SUV
  // beside one 2.64 m high M113). 1: one entry keeps its family (before; Params, classify.ini).
  std::size_t family_entries = 1;
  // A class's envelope (docs/decisions/open-set.md, eighth round): for each class with at least
  // two entries, one more range: the smallest box holding their L W H, widened by this share
  // either way (lo x (1 - share), hi x (1 + share)); its profile expectations are the family's of
  // that name (none for a group name), and with entry_profile it is no class for a top whose
  // profile differs by more than that from every one of its entries' own. 0: off (before).
  double class_envelope = 0;
};

// Throws common::UsageError naming the option of the first value out of range.
void validate(const Params& params);

// What the shape cues measured (null / NaN when not measurable, e.g. no return numbers).
struct Features {
  std::size_t crop_points = 0, ground_points = 0, object_points = 0;
  double crop_spacing = 0;               // 1 / sqrt(crop points per m² of its top-view box)
  double density = 0;                    // object points per m² of its rectangle
  double spacing = 0;                    // 1 / sqrt(density)
  std::optional<double> ground_density;  // ground returns per m² of the crop outside the rectangle
  std::optional<double> fill;            // density / ground_density (with bridge_fill: off the shadows)
  // fill_tile_ground (§31): ground_density and fill are the tile's, the crop having left them unmeasured.
  bool fill_from_tile = false;
  // fill_tile_first (§46): that reference was the tile's first-return density.
  bool fill_from_first = false;
  // The area (m²) of the rectangle in the strips --bridge crossed, by their empty share (§27), and
  // with bridge_fill leaving it out, the fill over the whole rectangle (as without it).
  double shadow_area = 0;
  std::optional<double> fill_rectangle;
  double heading_pca = 0;      // rad, the principal axis (for comparison only)
  double heading_hull = 0;     // rad, the minimum-area rectangle before refinement
  double heading_refined = 0;  // rad, the hull's axis refined by two parallel side lines (for comparison)
  double heading = 0;          // rad, the long axis used (the minimum-area rectangle's), in (-pi/2, pi/2]
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // rectangle centre (candidate frame)
  double length_measured = 0, width_measured = 0, height_measured = 0;
  double length = 0, width = 0, height = 0;  // corrected
  double plateau_share = 0;                  // share of the long profile within the drop of the top
  double end_low = 0, end_high = 0;          // mean top height of the lower / higher end fifth, / H
  // Occupied share of the top-view cells (max(0.25 m, 2 x spacing)) of the emptier end fifth over
  // that of the middle three fifths (classify.md §15): a vehicle's ends fill its width (bumper,
  // bonnet, tail), a drawbar tapers, an ellipse leaves its rectangle's corners empty.
  double end_fill = 0;
  // The outline (classify.md §16): the profile's deepest bin under its upper convex hull (share
  // of H; a car's bonnet or boot under the cabin, none on a box or an ellipsoid), the
  // number of runs at least kDentDepth deep, and the narrower end's outermost slice: its width
  // (share of W) and its highest point (share of H).
  double notch = 0;
  // The notch over the bins sampled across the width only (kSampledShare of the median count;
  // classify.md §37): a bin with less than one row of samples may have lost its top, not stepped.
  double notch_sampled = 0;
  std::size_t dents = 0;
  // The top view's convex hull area over its minimum-area rectangle's, both grown by half the
  // spacing (classify.md §17): a rectangle with rounded corners (a vehicle) near 1, an ellipse (a
  // rock) pi/4 = 0.785. The hull ignores holes inside the outline (glass, dark paint).
  double rectangularity = 0;
  double tip_width = 0, tip_level = 0;
  // The shoulder (classify.md §30): over the middle three fifths of the length, the 0.9 quantile
  // of the heights of the points in the outer kShoulderBand of the half-width on either side, over
  // H. A car's or van's body is full width up to its shoulder (door tops, roof edge, mirrors:
  // 0.6-1.0); a stack of logs or pipes, a ridge tent or a dome narrows upward (0.4-0.55). Unset
  // under kShoulderPoints such points.
  std::optional<double> shoulder;
  // The rim (classify.md §38): over the same middle three fifths, the 0.9 quantile of the heights in
  // the shoulder's band (the outer 30% of the half-width) on the lower of its two sides less that of
  // the centre band (the inner 30%: |y| < kRimCentre x W / 2), over H. A car's or van's roof is
  // highest across its middle (<= 0; an SUV's roof rails ~0.03); a flatbed's side boards or an open
  // box's walls stand above its floor on both sides (> 0; something higher on one side only, a cab's
  // corner or a neighbour, is no rim). Unset under kShoulderPoints points on either side or in the
  // centre band.
  std::optional<double> rim;
  // The bed (classify.md §39): at each end, over kBedFrom to kBedTo of the length from it, in the
  // rim's bands: walls = the lower side's 0.9 quantile of its points' heights over the higher of the
  // two centre points on either side of each along the length (a bed's walls over its floor; a
  // bonnet's or windscreen's slope, as high at the sides as in the middle, never stands over those),
  // under = H less the higher side's 0.9 quantile of its heights (the walls under the cab's roof);
  // the smaller of the two over H, at the end where it is larger. A pickup's open bed behind its
  // cab: both > 0 (its walls 0.3-0.5 m over its floor, 0.5-0.7 m under its roof); a car's or van's
  // end is a bonnet, boot or roof as high in its middle as at its sides (walls <= 0), a flatbed's
  // boards are its top (under = 0). Unset under kShoulderPoints centre points, or side points with
  // centre points on both sides of them, at both ends.
  std::optional<double> bed;
  double top_roughness = 0;   // median |interior cell top - the plane of its 3 x 3 cells' tops| (m)
  std::size_t top_cells = 0;  // interior cells with enough neighbours for it
  // Median over the interior cells of the smallest |top - the line through its nearest occupied
  // neighbours (up to two cells away) on either side| over four directions (along, across, the two
  // diagonals) (m; classify.md §19), and the cells that had a line.
  double top_roughness_line = 0;
  std::size_t top_cells_line = 0;
  double below_share = 0;     // interior object points with an object point >= 0.5 m above them
  double ground_through = 0;  // interior ground returns under an object point (share of interior returns)
  std::size_t interior_points = 0;
  // With sight_lines (§20) below_share and ground_through count only the points seen through the
  // object; these are every point's shares (the cues without it).
  std::optional<double> below_share_any, ground_through_any;
  // With ground_through_edges (§23): the ground returns ground_through set aside as edge splits.
  std::optional<std::size_t> ground_edge_splits;
  double below_share_cells = 0;     // the same per cell (for comparison): occupied cells with a point
  double ground_through_cells = 0;  // >= 0.5 m under their top; cells holding a ground return
  std::size_t interior_cells = 0;
  // Passes (classify.md §14): in the crop, holding the object (>= pass_share of its points);
  // fill and ground_through over every pass, as before (only when the crop has > 1 pass).
  std::size_t passes = 1, object_passes = 1;
  std::optional<double> fill_all_passes, ground_through_all_passes;
  // The object's median echo width over the open ground's single returns' (classify.md §25; the
  // realistic sensor's echo_width; unset without it).
  std::optional<double> echo_widening;
  std::optional<double> late_returns;  // share of object points with return_number > 1 (with
                                       // late_returns_inside: split inside the object, §22;
                                       // with late_shadow: weighed by ring_shadowed, §26)
  // The crop's ground returns outside the object's rectangle with known return numbers (the
  // passes that saw the object) and the share of them that are later returns (§26: the shade
  // around the object; unset under 10 such returns or without return numbers).
  std::size_t ring_returns = 0;
  std::optional<double> ring_shadowed;
  // The object's later returns whose pulse met something first above its top or outside the
  // crop, as a share of its points of known return number (with late_returns_inside or
  // late_shadow and gps_time; §22, §26).
  std::optional<double> late_shadowed;
  std::optional<double> multi_returns;  // share with number_of_returns > 1
};

// The answer.
struct Answer {
  std::string cls;     // fine class, "" = none
  std::string group;   // "" = none
  std::string reason;  // "" for a vehicle; too_sparse, vegetation_like, too_small, too_large,
                       // too_flat, not_vehicle_shape
  std::string detail;  // one sentence: the measured value against its threshold
  // The kind of evidence a none rests on ("" for a vehicle): "density" (too_sparse), "surface"
  // (vegetation_like: porous, rough, returns under it), "size" (too_large, too_small, too_flat,
  // or a size no class's ranges hold), "shape" (not_vehicle_shape for its top or outline: no
  // roof, a flat box, an open end, a drawbar, no bonnet or boot, an oval, a step).
  std::string refused_on;
  std::string entry;  // the class came from this modelbase entry's range ("" = a family's)
  double confidence = 0;
  double class_score = 0, class_margin = 0;  // size fit of the class, margin over another group
  Features features;
  bool measured = false;  // the rectangle and size were measured (enough points)
};

struct ModelEntry {
  std::string name, cls;
  std::array<double, 3> size{};  // L W H of its surface's label-1 rows
  // Its top's profile measured on its surface as on a candidate (plateau share, end levels):
  // its class range's profile expectations and flat-box flag. Not measured: the family's.
  struct Profile {
    double plateau_share = 0, end_low = 0, end_high = 0, end_fill = 1;
  };
  std::optional<Profile> profile;
};

// The class table run() decides among: the families, then (params.entry_classes) one range per
// entry: L W H x [1 - entry_tolerance, 1 + entry_tolerance], with the entry's own profile as its
// expectations (plateau and tail against plateau_split / tail_split; a flat box when its top is
// one, box_plateau / box_ends) or, unmeasured, the family's of the same name (none for others).
std::vector<TableRange> class_table(const Params& params, const std::vector<ModelEntry>& entries);

struct Inputs {
  formats::PointCloud cloud;          // the candidate PCD (local frame)
  std::string name;                   // its path, for errors
  std::vector<ModelEntry> modelbase;  // entries with a class (--modelbase), or none
  // The tile's open-ground density (detect's index density.ground, points/m²), for
  // Params::fill_tile_ground; none without --index.
  std::optional<double> tile_ground_density = std::nullopt;
  // tile_ground_density is the tile's first-return density (Params::fill_tile_first).
  bool tile_ground_from_first = false;
};

using Outputs = Answer;

// Features of the candidate's object, then the decision.
Outputs run(const Params& params, const Inputs& inputs);

// The nearest modelbase entry of the answer's class by L W H (Euclidean), or nullptr.
const ModelEntry* nearest(const Answer& answer, const std::vector<ModelEntry>& entries);

// The verdict document (canopy.verdict v1 with "level": "class"; formats/README.md "Verdict").
struct Document {
  formats::Provenance provenance;
  std::string candidate;                       // points path, as given
  std::optional<Eigen::Isometry3d> transform;  // candidate frame -> tile frame
  const ModelEntry* nearest = nullptr;
};
std::string serialize(const Answer& answer, const Params& params, const Document& doc);

// A candidate's transform from detect's index (canopy.candidates v1 or v2, read from the file
// `name`): the entry whose id is `id`. Errors name the file. (The tile's open-ground density for
// Params::fill_tile_ground is the same index's Candidates::density_ground(): read once.)
Eigen::Isometry3d index_transform(const documents::Candidates& index, const std::string& name,
                                  const std::string& id);
// "r00,r01,r02,t0,...[,0,0,0,1]": 12 or 16 numbers, row-major, rigid. UsageError otherwise.
Eigen::Isometry3d parse_transform(const std::string& text);

}  // namespace canopy::classify
