// rangetrace's tiles (tile_render.cpp, tile_sensor.cpp): rendering a tile built by the
// simulator (canopy/sim/tile.h: recipe, geometry, images, sensor plan) with POV-Ray, one frame
// per image (red + green carry the depth along the ray, coarse + fine, 32 bits; blue the class
// and vehicle instance), decoding the frames into the scan, its truth.json and its picture.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "canopy/formats/point_cloud.h"
#include "canopy/sim/tile.h"
#include "rangetrace/rangetrace.h"

namespace canopy::rangetrace {

// sim::build_tile with the run's seed and POV-Ray program.
Tile build_tile(const TileRecipe& recipe, const std::string& name, const Params& params);

// Depth along the view's ray at pixel (i, j), class and instance; false when the ray hit
// nothing inside the coded depth range.
bool decode_pixel(const Image16& img, const TileView& view, int i, int j, double* depth, std::uint32_t* cls,
                  std::int32_t* instance);

struct TileScan {
  formats::PointCloud cloud;
  std::vector<std::size_t> points_per_view;
  std::vector<double> area_per_view;
};
// Renders every view and the canopy image; fills the vehicles' canopy_cover.
TileScan run_tile(Tile* tile, const Params& params);
// The scan of a tile's images: image(k) is the frame of view k (views[0], the canopy image, is
// not decoded); each image keeps its points inside the tile and its view's strip (view_idx
// k - 1), in pixel order, shifted by the recipe's origin.
TileScan decode_tile(const std::function<Image16(int)>& image, const std::vector<TileView>& views,
                     const TileRecipe& recipe);
// truth.json text.
std::string truth_json(const Tile& tile, const std::vector<std::pair<std::string, std::string>>& params);
// Shaded nadir picture of the tile with vehicle footprints (red) and clutter boxes (yellow).
std::string render_tile_picture(const Tile& tile, const Params& params);

// Decodes one depth/label frame into points (tile frame) with class and instance.
struct TileHits {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::uint32_t> cls;
  std::vector<std::int32_t> instance;
  std::vector<std::size_t> pixel;
};
void decode_tile_view(const Image16& img, const TileView& view, TileHits* out);
// Fraction of the footprint polygon's pixels (centres inside) whose first hit from nadir is
// vegetation; `img` is the rendered nadir view.
double footprint_cover(const Image16& img, const TileView& view,
                       const std::array<Eigen::Vector2d, 4>& footprint);
// The pixels of a scan image (not the canopy image) that can give a kept point: the view's
// strip inside the tile (append_view keeps only those) between heights zlo and zhi (the tile's
// lowest ground and top, with the margin tile_views fits the image to), projected along
// -toward onto the image (pixel_origin's convention), rounded outwards, widened by `margin`
// pixels and clipped to the image (docs/decisions/cost.md §11).
PixelWindow strip_window(const TileView& view, const TileRecipe& recipe, double zlo, double zhi,
                         int margin = 2);

}  // namespace canopy::rangetrace
