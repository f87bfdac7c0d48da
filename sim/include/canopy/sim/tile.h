// Tiles (the simulator's scene geometry): a forest tile with terrain, trees, bushes, clutter and
// any number of vehicles, scanned along flight lines (issue 13; share/scenes/README.md documents
// the keys): its recipe, its geometry and placement, its images and its sensor plan. Rendering
// and decoding them is rangetrace's (tools/rangetrace/tile.h).
//
// Tile frame: right-handed, z up, metres; the tile is [0, extent_x] x [0, extent_y] and the
// terrain passes through z = 0 at the tile centre. With `origin = E N H` every output
// coordinate is shifted by (E, N, H) (written as float64).
//
// Rendering differs from the single-vehicle scenes (which keep their two-pass coding so the
// thesis scans stay byte-identical): one frame per image; every pixel's ray is known from the
// orthographic camera, so red + green carry the depth along the ray (coarse + fine, 32 bits)
// and blue the class and vehicle instance.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "canopy/common/math.h"
#include "canopy/sim/model.h"
#include "canopy/sim/sensor.h"

namespace canopy::sim {

// ---------------------------------------------------------------- recipe

struct VehicleSpec {
  std::string model;  // built-in name or a path (resolved against the recipe's directory)
  double x = 0, y = 0, heading = 0;
  MeshImport import;
  int line = 0;  // recipe line (errors name it)
};

struct ObjectSpec {
  std::string kind;  // one of kClutterKinds
  double x = 0, y = 0, heading = 0;
  int line = 0;
};

struct TreeSpec {
  bool conifer = false;
  double x = 0, y = 0, height = 16;
  int line = 0;
};

// A horizontal opaque disc labelled vegetation (an analytic canopy for tests and checks).
struct CanopyDisc {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 1;
};

struct Look {
  double elevation = 75 * common::kPi / 180;  // rad, (0, 90 deg]
  double azimuth = 0;  // rad: direction toward the sensor, relative to the flight heading
};

enum class Terrain { kFlat, kSlope, kRolling };

struct TileRecipe {
  double extent_x = 40, extent_y = 40;  // m, each in [5, 100]
  Terrain terrain = Terrain::kFlat;
  double slope = 0;                // rad, <= 15 deg
  double slope_azimuth = 0;        // rad, direction of steepest ascent
  double rolling_amplitude = 2;    // m, heights within +-amplitude (<= 2 m)
  double rolling_wavelength = 20;  // m, typical wavelength of the height field

  double trees_per_ha = 600;    // random trees per hectare
  double conifer_share = 0.4;   // share of random trees that are conifers
  double bushes_per_ha = 500;   // random understory bushes per hectare
  int hide = -1;                // trees planted beside each vehicle (concealment); -1: 2 if trees > 0, else 0
  std::vector<TreeSpec> trees;  // hand-placed trees
  std::vector<CanopyDisc> discs;  // hand-placed opaque canopy discs

  std::vector<VehicleSpec> vehicles;  // hand-placed
  int random_vehicles = 0;            // `vehicles = random N from a,b`
  std::vector<std::string> random_models;
  int random_line = 0;

  std::vector<ObjectSpec> objects;                   // hand-placed clutter
  std::vector<std::pair<std::string, int>> clutter;  // kind -> random count
  std::vector<int> clutter_lines;

  int flight_lines = 2;
  std::vector<double> headings = {0, common::kPi / 2};  // rad, flight directions (from +x, ccw)
  std::vector<Look> looks = {{75 * common::kPi / 180, 0}, {75 * common::kPi / 180, common::kPi}};
  double altitude = 300;         // m above the tile centre's ground
  double spacing = 0.08;         // m, pixel spacing perpendicular to the rays
  double swath_overlap = 0.2;    // extra swath width, share of the line spacing
  double canopy_spacing = 0.05;  // m, pixel spacing of the nadir canopy image

  bool has_origin = false;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // easting, northing, height

  // Sensor mode (issue 28): `sensor = NAME` and/or `sensor.KEY = VALUE` lines; the sensor is
  // resolved (preset + keys) by check_tile. Without them the tile is imaged as before.
  std::string sensor_name;
  int sensor_line = 0;
  struct SensorLine {
    std::string key;
    std::vector<std::string> words;
    int line = 0;
  };
  std::vector<SensorLine> sensor_lines;
  std::optional<Sensor> sensor;
  // Sensor mode: the flight lines are planned this far to the left of the tile's centre line
  // (across the first heading), so that the tile lies off the swath's centre (`swath_offset`).
  double swath_offset = 0;

  std::string dir;  // the recipe's directory ("" = current)
  // The line of each key given once (every key but tree, canopy_disc, vehicle, object and
  // clutter, which may repeat): errors about a value or the tile's size name it.
  std::map<std::string, int> lines;
};

// Resolves the recipe's sensor (preset, then its sensor.KEY lines) and refuses image-mode keys
// with it; DataError naming `name` and the line. Called before check_tile.
void resolve_sensor(TileRecipe* tile, const std::string& name);

// Keys that make a recipe a tile recipe.
bool is_tile_key(const std::string& key);
// Keys that may be given on several lines (each adds one item); any other key once.
bool is_repeatable_key(const std::string& key);
// Applies one tile key (words = the value split at blanks); throws common::UsageError with a
// message (the caller adds the file and line).
void apply_tile_key(TileRecipe* tile, const std::string& key, const std::vector<std::string>& words, int line);
// Checks ranges after the whole recipe is read, and that the tile's images cannot exceed the
// pixel budget whatever its terrain and trees (check_tile_budget on the flat, empty tile, a
// lower bound); throws DataError naming `name` and the line.
void check_tile(const TileRecipe& tile, const std::string& name);

// The most pixels a tile's images (its scan images and the canopy image) may have in all:
// each pixel gives at most one point, so this bounds the points (memory: ~180 bytes each at
// peak, measured), the frames in TMPDIR (6 bytes a pixel) and POV-Ray's time.
constexpr double kMaxTilePixels = 3e7;
// The largest image side rendered.
constexpr double kMaxImageSide = 16384;

// ---------------------------------------------------------------- geometry

enum class Class : std::uint32_t { kGround = 0, kVegetation = 1, kClutter = 2, kVehicle = 3 };

// A triangle mesh in a local frame (world axes, metres).
struct TriMesh {
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<int, 3>> f;
  void box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
  // Tapered n-gon prism from a (radius ra) to b (radius rb).
  void limb(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double ra, double rb, int sides);
  void triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);
  void append(const TriMesh& other);
};

// The terrain: height and its piecewise-linear mesh (rolling) or plane (flat, slope).
class TerrainModel {
 public:
  TerrainModel(const TileRecipe& tile, std::uint64_t seed);
  double height(double x, double y) const;
  Eigen::Vector3d normal(double x, double y) const;  // of the plane; of the triangle (rolling)
  double lo() const { return lo_; }
  double hi() const { return hi_; }
  // POV-Ray code of the ground object (no texture).
  std::string pov() const;
  bool planar() const { return planar_; }

 private:
  bool planar_ = true;
  Eigen::Vector3d plane_n_ = Eigen::Vector3d::UnitZ();
  double cx_ = 0, cy_ = 0;  // tile centre
  double x0_ = 0, y0_ = 0, step_ = 1;
  int nx_ = 0, ny_ = 0;
  std::vector<double> h_;  // rolling: (nx_+1) x (ny_+1) grid heights
  double lo_ = 0, hi_ = 0;
  double grid(int i, int j) const;
};

// Pose of a rigid object standing on the terrain: rotation R (columns: forward, left, up),
// translation of its anchor (bottom centre of its bounding box) and the Tait-Bryan angles
// R = Rz(heading) Ry(pitch) Rx(roll).
struct Posed {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
  double heading = 0, pitch = 0, roll = 0;
  Eigen::Affine3d transform() const;  // local (anchor at origin) -> tile
};
// Stands a box of half-length hl and half-width hw (local x, y) on the terrain at (x, y) with
// `heading`: its up axis follows the plane through the ground under its four corners, raised
// so that no corner is below the ground.
Posed stand_on(const TerrainModel& terrain, double x, double y, double heading, double hl, double hw);

struct PlacedVehicle {
  int instance = 0;  // 1-based
  std::string model_name;
  int model_index = 0;       // into Tile::models
  Eigen::Vector3d size;      // bounding box L x W x H
  Eigen::Vector3d model_lo;  // bounding box as declared by the model (tile axes)
  Posed pose;
  std::array<Eigen::Vector2d, 4> footprint;  // top view, counter-clockwise
  double canopy_cover = -1;                  // measured
  int line = 0;
};

struct PlacedObject {
  std::string kind;
  int template_index = 0;  // into Tile::object_meshes
  Eigen::Vector3d size;    // local box
  Eigen::Vector3d lo;      // its low corner (local; the anchor is the local origin)
  Posed pose;
};

struct PlacedTree {
  int template_index = 0;  // into Tile::tree_meshes
  Eigen::Vector3d base;    // trunk base on the ground
  double rotation = 0;     // about z
  double scale = 1;
  bool bush = false;
  bool conifer = false;
};

// One pulse aimed into the tile: when, from where, which way, where its axis meets the terrain.
struct Pulse {
  double time = 0;  // s (GPS time of week)
  Eigen::Vector3d sensor = Eigen::Vector3d::Zero(), dir = Eigen::Vector3d::UnitZ(),
                  ground = Eigen::Vector3d::Zero();
  double scan_angle = 0;  // rad, + = right of the flight direction
  int line = 0;           // 1-based flight line (point source id)
  int view = 0;           // its image (SensorPlan::views)
  bool scan_dir = true;
};

struct FlightLine {
  int id = 0;                  // point source id
  double heading = 0;          // rad, direction flown
  double offset = 0;           // m, across-track offset of the line from the tile centre
  Eigen::Vector3d start, end;  // sensor positions (tile frame)
  double t0 = 0, t1 = 0;       // GPS time at start and end
};

struct Tile {
  TileRecipe recipe;
  std::string name;
  std::uint64_t seed = 1;
  std::vector<Model> models;                                              // distinct vehicle models
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> model_bounds;  // per model
  std::vector<PlacedVehicle> vehicles;
  std::vector<TriMesh> object_meshes;
  std::vector<PlacedObject> objects;
  std::vector<TriMesh> tree_meshes;  // templates: trees and bushes
  std::vector<PlacedTree> trees;
  double top = 0;            // highest point of anything (m)
  double canopy_cover = -1;  // measured: share of the tile hidden from nadir
  // Sensor mode: what run_tile measured (truth.json "density", "flight_lines").
  std::vector<FlightLine> flight_lines;
  double returns_per_m2 = 0, pulses_per_m2 = 0, fired_per_m2 = 0;
  std::vector<std::size_t> pulses_by_returns;
};

// Broadleaf, conifer and bush templates (tree height 1 at scale 1 is not used: templates are
// full-size, `scale` varies them by +-15%).
TriMesh broadleaf_template(std::uint64_t seed, double height);
TriMesh conifer_template(std::uint64_t seed, double height);
TriMesh bush_template(std::uint64_t seed, double radius);
TriMesh clutter_mesh(const std::string& kind, std::uint64_t seed);
// The clutter kinds: the five the thresholds were fitted on (boulder .. logs), then issue 29's
// unseen ones (trailer .. rock; share/scenes/README.md documents each kind's sizes).
constexpr int kClutterKindCount = 11;
extern const char* const kClutterKinds[kClutterKindCount];

// POV-Ray text of a mesh as `#declare <name> = mesh2 {...}` (tile axes -> POV-Ray frame).
std::string mesh_declare(const std::string& name, const TriMesh& mesh);

// Loads the recipe's vehicle models (extents from one POV-Ray parse run) and places
// everything; throws DataError naming the recipe line for vehicles outside the tile,
// overlapping vehicles and unreadable model files.
// Random phases draw from seeds derived from `seed`; `povray` is the program that measures the
// models' extents (povray_run.h).
Tile build_tile(const TileRecipe& recipe, const std::string& name, std::uint64_t seed,
                const std::string& povray);

// ---------------------------------------------------------------- rendering

// One image: an orthographic camera; pixel (i, j) (column, row from the top) shoots from
// origin + ((i + .5)/W - .5) right + (.5 - (j + .5)/H) up along -toward.
struct TileView {
  Eigen::Vector3d toward = Eigen::Vector3d::UnitZ();  // unit, from the scene toward the sensor
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   // image-plane centre
  Eigen::Vector3d right = Eigen::Vector3d::UnitX(), up = Eigen::Vector3d::UnitY();  // unit
  int width = 0, height = 0;
  double pixels_x = 0, pixels_y = 0;  // the size asked for (width, height before any clamping)
  double spacing = 0;
  double depth_lo = 0, depth_span = 0;  // depth along the ray is coded over lo + [0, span]
  // Points are kept inside this strip (tile coordinates): |(p - strip_centre) . across| <= half.
  Eigen::Vector2d strip_centre = Eigen::Vector2d::Zero(), strip_across = Eigen::Vector2d::UnitY();
  double strip_half = 0;
  int line = 0, heading_idx = 0, look_idx = 0;  // the pass and look it belongs to
  double strip_area = 0;                        // m^2 of the strip inside the tile
};
std::vector<TileView> tile_views(const Tile& tile);
// The nadir view over the whole tile used to measure canopy cover.
TileView canopy_view(const Tile& tile);
// The same for a recipe whose ground and objects span heights [ground_lo, top] (a Tile's:
// its terrain's lowest point and its top); tile_views.cpp, with the budget check.
std::vector<TileView> tile_views(const TileRecipe& recipe, double ground_lo, double top);
TileView canopy_view(const TileRecipe& recipe, double ground_lo, double top);
// Throws a DataError naming `name` and the recipe's line (spacing, canopy_spacing, else the
// first of extent, looks, headings, flight_lines, swath_overlap given) when the images
// (views[0] the canopy image, then the scan images) have more than kMaxTilePixels pixels in
// all or a side longer than kMaxImageSide.
void check_tile_budget(const std::vector<TileView>& views, const TileRecipe& recipe, const std::string& name);

// ---------------------------------------------------------------- sensor mode (sensor_plan.cpp)

struct SensorPlan {
  Sensor sensor;
  std::vector<FlightLine> lines;
  std::vector<Pulse> pulses;    // in time order
  std::vector<TileView> views;  // one per (line, scan-direction bin) holding pulses
  double fired = 0;             // pulses fired along the lines (into the tile or not)
  double spacing = 0;           // m, the images' pixel (sub-ray) spacing
};
// The flight lines, pulses and images of a sensor-mode tile (sensor_plan.cpp); `terrain` gives
// the ground height at (x, y), empty = flat at z 0 (the
// budget check before the tile is built). Throws DataError naming `name` when the lines would
// fire more than 5e7 pulses.
SensorPlan plan_sensor(const TileRecipe& recipe, const std::function<double(double, double)>& terrain,
                       double ground_lo, double top, const std::string& name);

// True when p lies inside the convex quadrilateral `poly` (counter-clockwise).
bool in_polygon(const Eigen::Vector2d& p, const std::array<Eigen::Vector2d, 4>& poly);

}  // namespace canopy::sim
