// Sensor-mode sampling (tile_sensor.cpp): a pulse's sub-rays from its bin image, and the whole
// tile's returns as LAS-ready columns.
#pragma once

#include <functional>
#include <vector>

#include "canopy/formats/trajectory.h"
#include "rangetrace/tile.h"

namespace canopy::rangetrace {

// Reflectance of what a sub-ray hit: its point (tile frame), class and instance.
using SurfaceReflectance = std::function<double(const Eigen::Vector3d&, std::uint32_t, std::int32_t)>;
// The tile's surfaces under sensor `s` (sensor.h: ground, vegetation, clutter, each vehicle's
// paint drawn from (seed, instance), glass in the greenhouse band of the cars that have one).
SurfaceReflectance tile_surfaces(const Sensor& s, const Tile& tile, std::uint64_t seed);

// The sub-rays of `pulse` in its image `img` (view `v`): the pixels whose centres lie inside the
// footprint (1/e^2 radius at the pulse's range), weighted by the Gaussian beam profile and
// normalised over the footprint, with the range along the pulse of what each hit. The energy a
// sub-ray returns is its weight times the reflectance of what it hit (`reflect`; none = 1).
std::vector<SubHit> sample_pulse(const Sensor& s, const Pulse& pulse, const TileView& v, const Image16& img,
                                 const SurfaceReflectance& reflect = {});

// The columns of a sensor-mode scan: x y z intensity return_number number_of_returns
// scan_direction_flag classification (ASPRS) scan_angle point_source_id gps_time, then label
// instance echo_width (LAS Extra Bytes).
void add_sensor_columns(formats::PointCloud* cloud);

// Every pulse of the plan sampled from its image (`image(k)` = the rendered plan.views[k]),
// detected, range noise added along the beam, returns inside the tile kept in pulse order;
// fills the tile's measured densities and flight lines.
TileScan sense_tile(const SensorPlan& plan, const std::function<Image16(int)>& image, Tile* tile,
                    std::uint64_t seed);

// The sensor's path (formats/trajectory.h): each flight line sampled at 10 Hz from its first to
// its last pulse time, in the points' frame (origin added), heading = the direction flown.
formats::Trajectory tile_trajectory(const Tile& tile);
// The trajectory file beside a scan: its name with the extension replaced by ".traj".
std::string trajectory_path(const std::string& scan);

}  // namespace canopy::rangetrace
