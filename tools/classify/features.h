// classify's measurements (classify.h steps 1-4): the candidate's points, its object, the
// object's rectangle, size and shape cues. Exposed for the tests.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"
#include "classify/classify.h"

namespace canopy::classify {

// Grid cells of `size` along one axis, and a top-view cell's hash key (cells within ±2^30: crops
// are a few tens of metres); shared by the object's clustering, its joins and the penetration cues.
inline std::int64_t cell_of(double v, double size) { return static_cast<std::int64_t>(std::floor(v / size)); }
inline std::uint64_t cell_key(std::int64_t x, std::int64_t y) {
  constexpr std::int64_t kBias = std::int64_t{1} << 30;
  return (static_cast<std::uint64_t>(x + kBias) << 32) | static_cast<std::uint64_t>(y + kBias);
}

// The fields classify reads: x y z, and return numbers when present (else empty vectors); the
// flight pass of each point when the file says which (point_source_id and/or gps_time, LAS).
struct Candidate {
  std::vector<Eigen::Vector3d> points;
  std::vector<int> return_number, number_of_returns;  // 0 = unknown
  // Per point: the pulse's flight line and time (point_source_id, gps_time); empty = unknown
  // (NaN: unknown for that point). The returns of one pulse share both.
  std::vector<double> source, time;
  // Unit direction from each point toward the sensor that saw it (sensor_x/y/z), empty = unknown.
  std::vector<Eigen::Vector3d> view;
  // Per point: the width (FWHM, m) of its echo in the waveform (the realistic sensor's
  // `echo_width`), empty = unknown (NaN: unknown for that point).
  std::vector<double> echo_width;
  // Pass index per point, 0 .. passes - 1 (empty = one pass, unknown): points of one flight line
  // (point_source_id) flown in one stretch of time (gps_time gaps of more than kPassGap s split
  // a line: a crop is crossed in well under a second; lines are minutes apart).
  std::vector<int> pass;
  std::size_t passes = 1;
  // The tile's open-ground density (points/m², detect's index density.ground), the reference of
  // `fill` where the crop has too little open ground (Params::fill_tile_ground); none: unknown.
  std::optional<double> tile_ground_density;
  // It is the tile's first-return density (density.first; Params::fill_tile_first).
  bool tile_ground_from_first = false;
};
constexpr double kPassGap = 10;  // s

// Passes from a flight-line id and a time per point (either may be empty): sorted by (id,
// time), a new pass at a new id or a time gap > kPassGap; numbered in that order.
std::vector<int> passes_of(const std::vector<double>& source, const std::vector<double>& time,
                           std::size_t* count);

// The crop's pulses (classify.md §22, §23): the returns of one pulse share point_source_id,
// gps_time and number_of_returns. A point whose time or source is unknown (NaN), or every point
// of a candidate without times, has none.
class Pulses {
 public:
  explicit Pulses(const Candidate& c);
  bool known(std::size_t i) const { return pulse_[i] >= 0; }
  // The crop points of point i's pulse, i among them, in crop order (known(i) only).
  const std::vector<std::size_t>& of(std::size_t i) const {
    return members_[static_cast<std::size_t>(pulse_[i])];
  }

 private:
  std::vector<std::ptrdiff_t> pulse_;  // per point: its pulse in members_, -1 none
  std::vector<std::vector<std::size_t>> members_;
};

// Errors name the file: x y z missing, a non-finite coordinate.
Candidate read_candidate(const formats::PointCloud& cloud, const std::string& name);

// A strip --bridge crossed (classify.md §27): x between the facing ends of the object and the
// joined cluster, y where both extend (candidate frame, top view), and `empty`, the share of it
// that returned nothing: 1 - its returns (ground and any other above-ground point in it) over
// what the crop's ground density puts there, in [0, 1].
// A top-view box grown point by point (u along, v across; empty: infinite bounds).
struct Extents {
  double u0 = std::numeric_limits<double>::infinity(), u1 = -std::numeric_limits<double>::infinity();
  double v0 = std::numeric_limits<double>::infinity(), v1 = -std::numeric_limits<double>::infinity();
  double length() const { return u1 - u0; }
  double width() const { return v1 - v0; }
  void add(double u, double v) {
    u0 = std::min(u0, u);
    u1 = std::max(u1, u);
    v0 = std::min(v0, v);
    v1 = std::max(v1, v);
  }
  bool outside(double u, double v) const { return u < u0 || u > u1 || v < v0 || v > v1; }
};

struct Shadow {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0, empty = 0;
};

// Indices of the object's points, with the options of `fp` (Params' ground_cut, bridge,
// bridge_length, join_stacked, bridge_min_share; the rest unused): the above-ground points (z >= ground_cut)
// clustered at distance `link`; the largest cluster whose top-view box (padded by `link`) holds the origin,
// else the largest. With `bridge` > 0 (classify.md §21) other clusters join it across gaps of up
// to `bridge` in the top view: a cluster inside the object's extent across x (the candidate
// frame's long axis; + `link`), whose top is no higher than
// the object's and at least half as high, nearest first, while the object stays at most
// `bridge_length` long; `crop_area` (m², the crop's top-view box, at least 1e-6) gives the
// crop's ground density the bridge compares its gap with. With `join_stacked` (classify.md §25)
// first every cluster that meets the object in the top view (within `link`) but is apart from it
// in height, lies beside it rather than over or under it (at most 25% of the smaller one's top-view
// cells hold points of the other), in line with it (the union no wider across the candidate
// frame's x axis than the wider of the two + 0.3 m) and holding at least 10% of the object's
// points joins it, until none does: seen from above a
// vertical face returns nothing, so a cab and its deck, a cab top and its body touch only in plan.
// With `bridge_min_share` > 0 (classify.md §27) a cluster joins across a gap only when it holds
// at least that share of the object's points (as the object stands); with `shadows` the strips the
// bridge crossed are appended to it.
std::vector<std::size_t> object_of(const Candidate& c, const Params& fp, double link, double crop_area,
                                   std::vector<Shadow>* shadows = nullptr);

// classify.md §25 (object_of with `join_stacked`): joins to the object (`in`, per point of `pts`)
// each cluster of `label` that meets it within `link` in the top view, beside it, in line with it
// and holding at least 10% of its points, until none joins.
void join_beside(const std::vector<Eigen::Vector3d>& pts, const std::vector<std::size_t>& label, double link,
                 std::vector<char>& in);

// classify.md §21 (object_of with `bridge`): joins to the object (`in`, per point of `pts`; the
// clusters of `label` rooted at `best`) the clusters its own no-return gaps split off; `ground`
// the crop's ground returns (top view), `ground_density` per m² of the crop. `min_share` and
// `shadows` as object_of's bridge_min_share and shadows.
void bridge_gaps(const std::vector<Eigen::Vector3d>& pts, const std::vector<std::size_t>& label,
                 std::size_t best, const std::vector<Eigen::Vector2d>& ground, double ground_density,
                 double link, double bridge, double bridge_length, std::vector<char>& in,
                 double min_share = 0, std::vector<Shadow>* shadows = nullptr);
// classify.md §27 (fill_empty_cells): the area (m²) of the rectangle [0, length] x [0, width]
// (coordinates along and across it) in cells of at least `cell` (as many whole cells as fit each
// side) that hold none of `points` (every return of the crop, in those coordinates).
double empty_area(const std::vector<Eigen::Vector2d>& points, double length, double width, double cell);
// classify.md §27: the object's points per m² of its rectangle (long axis `u`, across `v`, extents
// [u0, u1] x [v0, v1]) as fill counts them: f.density, or with fp.fill_empty_cells less the empty
// cells (empty_area over every point of `c`, cells of 2 x f.crop_spacing), else with fp.bridge_fill
// less the `shadows`; sets f.shadow_area (the cells' or the shadows' area, used or not).
double solid_density(const Candidate& c, const std::vector<Shadow>& shadows, const Params& fp,
                     const Eigen::Vector2d& u, const Eigen::Vector2d& v, double u0, double u1, double v0,
                     double v1, Features& f);
// classify.md §27: the area (m²) of the object's rectangle (its long axis along `u`, across `v`;
// extents [u0, u1] x [v0, v1] in those coordinates) that the shadows cover, each counted by its
// empty share (where shadows overlap, the largest), sampled on a grid of `step`.
double shadow_area(const std::vector<Shadow>& shadows, const Eigen::Vector2d& u, const Eigen::Vector2d& v,
                   double u0, double u1, double v0, double v1, double step = 0.02);
// --bridge: a gap between two clusters whose ground returns reach this share of the crop's ground
// density is open ground between two objects, not a vehicle's shadow.
constexpr double kGapGround = 0.25;

// The outline cues (classify.md §16) of the object's points `q` in its rectangle's frame (x along
// the long axis from 0 to length_measured, y across from its middle, z the height): notch,
// dents, tip_width, tip_level, shoulder (§30), rim (§38), bed (§39). Needs f's measured size and spacing.
void outline_cues(const std::vector<Eigen::Vector3d>& q, Features& f);
// A dent: a run of the profile at least this far (share of H) under its upper hull.
constexpr double kDentDepth = 0.05;
// The sampled notch's bins (classify.md §37): those holding at least this share of the filled
// bins' median count (under it: less than one row of samples across the width).
constexpr double kSampledShare = 0.5;
// The shoulder's band: |y| beyond this share of the half-width, over x in [0.2 L, 0.8 L]; and the
// least number of points in it for a shoulder (classify.md §30).
constexpr double kShoulderBand = 0.7;
constexpr std::size_t kShoulderPoints = 4;
// The rim's centre band (classify.md §38): |y| under this share of the half-width (the inner 30%,
// the shoulder band's mirror), over the same length; kShoulderPoints in it and on each side of the
// shoulder's band, or no rim.
constexpr double kRimCentre = 1 - kShoulderBand;
// The bed's window at each end (classify.md §39): from kBedFrom to kBedTo of the length from that
// end (a pickup's bed is its rear 0.3-0.6 of the length; its tailgate lies before kBedFrom).
constexpr double kBedFrom = 0.05;
constexpr double kBedTo = 0.27;

// Points under the object inside its footprint, point by point (a crown lets pulses through
// and holds returns at every depth; a roof holds none under it). Interior = at least `inset`
// from the rectangle's sides. below_share: interior object points with another object point
// within `rb` horizontally at least 0.5 m higher. ground_through: interior ground returns with
// an object point within `rg` horizontally above them, as a share of those and the interior
// object points. Small radii keep a thin part over open ground (a gun, lift arms, a chassis
// rail) from counting the ground beside it.
// Only the ground returns that `counted` marks are taken (the passes that saw the object); with
// `all` set, every pass's too, into ground_through_all_passes.
// With fp.sight_lines (classify.md §20) a point counts only when its line of sight (c.view) passes
// through the object above it (Params::sight_lines). `q` are the object's points (`object`: their
// indices in c) in the rectangle's frame: u from u0 along the long axis, v from vm across.
void penetration_cues(const Candidate& c, const std::vector<std::size_t>& object,
                      const std::vector<char>& counted, bool all, const std::vector<Eigen::Vector3d>& q,
                      double u0, double vm, const Eigen::Vector2d& u, const Eigen::Vector2d& v, Features& f,
                      const Params& fp);

// classify.md §25: f.echo_widening, the median echo width (c.echo_width) of the object's points
// over the median of the crop's ground points (below fp.ground_cut) that were the only return of
// their pulse; unset without echo widths, with fewer than 10 such ground returns or 3 object points.
void echo_cue(const Candidate& c, const std::vector<std::size_t>& object, const Params& fp, Features& f);

// classify.md §5, §22, §26: f.late_returns and f.multi_returns of the object's points (with return
// numbers) and, with fp.late_returns_inside or fp.late_shadow, f.late_shadowed, f.ring_returns and
// f.ring_shadowed (the crop's ground returns outside the rectangle u0..u1 along u, v0..v1 along v
// that `counted` marks, and their later-return share).
void late_cues(const Candidate& c, const std::vector<std::size_t>& object, const std::vector<char>& counted,
               const Eigen::Vector2d& u, const Eigen::Vector2d& v, double u0, double u1, double v0, double v1,
               const Params& fp, Features& f);

// Every measurement of Features (classify.h).
Features measure(const Candidate& c, const Params& params);

}  // namespace canopy::classify
