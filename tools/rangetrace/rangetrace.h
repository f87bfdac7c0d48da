// rangetrace: simulated airborne range scans with POV-Ray (thesis ch. 2, PIPELINE.md §3).
//
// Stock POV-Ray has no range output, so every view is rendered twice with emissive textures
// applied outermost (after every transform): pass 0 colours each hit by its world x, y, z
// (16-bit PPM, gamma 1, no antialiasing, no dithering), pass 1 by its ground-truth label.
// Each pixel decodes to one point; points outside the crop box are dropped.
//
// Frames: the world frame is right-handed, z up, ground z = 0, metres; POV-Ray's is left-handed,
// y up (sim::pov_frame converts). The engines (POV-Ray runner, models, families, tile geometry,
// sensor model) are the library canopy_sim (sim/); this is rangetrace's face over them.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "canopy/formats/point_cloud.h"
#include "canopy/formats/ppm.h"
#include "canopy/sim/model.h"

namespace canopy::sim {
struct TileRecipe;  // canopy/sim/tile.h
}  // namespace canopy::sim

namespace canopy::rangetrace {

// rangetrace is the simulator's face: the engines' names (canopy::sim) are its names too.
using namespace sim;

// ---------------------------------------------------------------- scenes

// One camera: the unit vector from the target toward the sensor, from its azimuth (about +z,
// counter-clockwise from the vehicle's long axis) and elevation above the ground plane.
struct View {
  double azimuth = 0;    // rad, relative to the vehicle heading
  double elevation = 0;  // rad, in (0, pi/2)
};

// A scene recipe: the views and the foliage. Text format (one "key = value" per line, '#'
// starts a comment, lengths and angles take units as on the command line):
//   foliage_count = 500        foliage_radius = 100mm
//   foliage_band = 2m          foliage_square = 12.2m
//   views = circle N ELEV            N views evenly spaced on a circle, azimuth 0 first
//   views = flyby N ELEV START       two straight passes of N views, one in front of the
//                                    nose (x > 0) and one behind the tail, from bearing
//                                    START off the long axis to -START
//   views = dodecahedron             the vertices of a dodecahedron with one face up that
//                                    lie above the ground (10)
//   view = AZIMUTH ELEVATION         one explicit view
// `views`/`view` lines append in file order. Counts are bounded (views <= 1000 per line and
// 10000 in all, foliage_count <= 100000) with errors naming the line.
// A recipe using any tile key (tile.h, share/scenes/README.md) is a tile: `tile` is set and
// the single-vehicle keys above are refused.
struct SceneRecipe {
  std::string name;
  int foliage_count = 0;
  double foliage_radius = 0.1;   // m
  double foliage_band = 2.0;     // m, height of the band above the vehicle's top
  double foliage_square = 12.2;  // m, side of the square, centred on the vehicle
  std::vector<View> views;
  std::shared_ptr<TileRecipe> tile;  // set for tile recipes
};

// Parses a recipe; `name` is used in errors ("<name>: line 3: ...") and as the scene name.
SceneRecipe parse_scene(const std::string& text, const std::string& name);
// A short name (no '/' or '.') of a recipe in share/scenes/ (circle, flyby, unoccluded, forest,
// ...: share/scenes/<name>.scene, found before a file of that name in the working directory)
// or a recipe path. An unknown short name that is no file is a UsageError.
SceneRecipe load_scene(const std::string& name_or_path);

std::vector<View> circle_views(int count, double elevation);
std::vector<View> flyby_views(int per_pass, double elevation, double start_bearing);
std::vector<View> dodecahedron_views();

// A thin disc of foliage, world frame.
struct Disc {
  Eigen::Vector3d centre;
  Eigen::Vector3d normal;  // unit
  double radius = 0;
};

// The vehicle as placed in the world: heading (rad, about +z from +x) and ground position.
struct Pose {
  double heading = 0;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
};

// `count` discs with centres uniform in the square of side `square` centred on the vehicle
// (aligned with its heading) and heights uniform in [top, top + band]; normals uniform on the
// sphere. Drawn from Rng(derive_seed(seed, "foliage")): portable and reproducible.
std::vector<Disc> make_foliage(const SceneRecipe& scene, const Pose& pose, double top, std::uint64_t seed);

// ---------------------------------------------------------------- rendering

struct Params {
  // The CLI's options of the same names; validate() checks them.
  int size = 512;             // image width = height (pixels)
  double spacing = 0.030;     // pixel spacing on the image plane (m): field = size * spacing
  double crop_length = 10.0;  // crop box along the vehicle's long axis (m)
  double crop_width = 4.0;    // across (m)
  double crop_height = 4.0;   // vertical (m); the box is centred on the vehicle's bounding box
  Pose pose;
  std::uint64_t seed = 1;
  int threads = 2;  // concurrent POV-Ray processes
  std::string povray = "povray";
  // Each POV-Ray run (a block of views) traces only the union of its views' crop_window: the
  // same scan, fewer pixels (docs/decisions/cost.md §11). false traces every pixel
  // (CANOPY_RENDER_WINDOW=off).
  bool window = true;
  // Tiles: the canopy image (read for its classes only) is rendered with red and green 0, without
  // evaluating the depth functions: the same classes, less CPU (cost.md §13). false codes depth
  // there too (CANOPY_CANOPY_CLASS_ONLY=off).
  bool canopy_class_only = true;
};

// Throws common::UsageError naming the options when size is outside [8, 8192] or the spacing
// or a crop size is not > 0.
void validate(const Params& params);

// The vehicle's bounding box in the world after placement (from POV-Ray's min/max_extent).
struct Placement {
  Eigen::Vector3d model_min, model_max;  // world frame, as declared in the model
  Eigen::Affine3d transform;             // model -> world (centre on ground, heading, position)
  Eigen::Vector3d centre;                // placed bounding-box centre
  double top = 0;                        // placed height (m)
};
Placement place(const Eigen::Vector3d& model_min, const Eigen::Vector3d& model_max, const Pose& pose);

// Box in which colours encode coordinates: the crop box's axis-aligned bounds plus a margin.
struct Encoding {
  Eigen::Vector3d lo, span;
};
Encoding encoding_for(const Placement& placement, const Params& params);

// The POV-Ray scene of all views: frame 2k renders view k's coordinates, frame 2k+1 its
// labels. `picture` > 0 instead renders a shaded picture (1: view 0 of the scene, 2: the model
// alone from an oblique perspective).
std::string scene_pov(const Model& model, const Placement& placement, const Encoding& enc,
                      const std::vector<View>& views, const std::vector<Disc>& foliage, const Params& params,
                      int picture = 0);
// Unit vector from the target toward the sensor of a view, world frame.
Eigen::Vector3d view_direction(const View& view, const Pose& pose);

// POV-Ray's frames are 16-bit PPM, decoded by formats/ppm.h.
using formats::Image16;
using formats::parse_ppm;

// Appends the decoded, cropped points of one view to the scan columns.
struct ScanColumns {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> sensor;
  std::vector<std::int32_t> view_idx;
  std::vector<std::uint32_t> label;
};
void decode_view(const Image16& coords, const Image16& labels, const Encoding& enc, const Placement& placement,
                 const Params& params, const Eigen::Vector3d& toward, int view_idx, ScanColumns* out);
// True when p lies in the crop box (oriented with the heading, centred on the vehicle).
bool in_crop(const Eigen::Vector3d& p, const Placement& placement, const Params& params);

// Pixels (0-based, inclusive) of a view's params.size x params.size image.
struct PixelWindow {
  int col0 = 0, col1 = 0, row0 = 0, row1 = 0;
};
// The pixels of `view`'s image whose rays can pass through the crop box: the bounding box of
// the box's 8 corners projected as POV-Ray projects them (orthographic camera at the view's
// direction, look_at the box centre, which is the placed vehicle's centre wherever it is placed, sky +z;
// pixel (i, j) traces the ray through
// ((i + 0.5) / size - 0.5, 0.5 - (j + 0.5) / size) of the field), rounded outwards and widened
// by `margin` pixels, clipped to the image. Every kept point (in_crop) lies on such a ray, so
// the pixels outside give no point. The whole image for a view straight down (POV-Ray's
// look_at then keeps its own right vector).
PixelWindow crop_window(const Params& params, const View& view, int margin = 2);
// The smallest window holding every one of `ws` (not empty): what a run of several views traces.
PixelWindow window_union(const std::vector<PixelWindow>& ws);

// ---------------------------------------------------------------- running POV-Ray

// The model's bounding box as declared (world frame, m), from POV-Ray's min/max_extent.
std::pair<Eigen::Vector3d, Eigen::Vector3d> model_bounds(const Model& model, const Params& params);

// Renders the range scan: parses the model's extents, places it, renders every view in
// parallel, decodes and crops. Throws Error with POV-Ray's own message when it fails.
formats::PointCloud render_scan(const Model& model, const SceneRecipe& scene, const Params& params);

// Renders a shaded picture (8-bit PNG bytes): with a scene, its view `view_idx` with foliage;
// without (scene == nullptr), the model alone on the ground from an oblique perspective.
std::string render_picture(const Model& model, const SceneRecipe* scene, int view_idx, const Params& params);

}  // namespace canopy::rangetrace
