// topview: a tile seen from straight above, north up: height above ground as a colour ramp
// shaded by the relief, the candidates outlined by outcome (detected at model level, at class
// level, none, rejected for a reason, failed; or, with a score, right / wrong / false alarm),
// the true footprints, and a legend with the counts, a scale bar in metres and the pixel size
// (docs/decisions/topview.md).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/height_raster.h"
#include "canopy/formats/point_cloud.h"

namespace canopy::topview {

using Rgb = std::array<std::uint8_t, 3>;
using Ring = std::vector<std::array<double, 2>>;

// What an outline shows, drawn in this order (later ones on top).
enum class Kind {
  truth,        // a true vehicle (found, or no score given)
  missed,       // a true vehicle the score says nothing matched
  none,         // a candidate the chain looked at and said "no vehicle"
  rejected,     // a candidate rejected for another reason (too sparse, too small, ...)
  failed,       // a candidate whose chain failed
  cls,          // detected at class level (no model)
  model,        // detected at model level (every v1 detection)
  right,        // with a score: matched, right (the model, or at the class level the class)
  wrong,        // with a score: matched, wrong (model, or class at the class level)
  false_alarm,  // with a score: matched nothing
};
inline constexpr int kKinds = 10;

// Outline colours (each outline has a one-pixel black border so it reads on any height).
inline constexpr Rgb kTruth{255, 255, 255};
inline constexpr Rgb kMissed{255, 220, 0};
inline constexpr Rgb kNone{175, 120, 255};
inline constexpr Rgb kRejected{255, 120, 190};
inline constexpr Rgb kFailed{255, 40, 40};
inline constexpr Rgb kClass{0, 190, 255};
inline constexpr Rgb kModel{0, 230, 0};
inline constexpr Rgb kRight{0, 230, 0};
inline constexpr Rgb kWrong{255, 140, 0};
inline constexpr Rgb kFalseAlarm{230, 0, 230};
inline constexpr Rgb kNoData{28, 28, 28};  // a pixel with no point and no filled neighbour

Rgb colour_of(Kind kind);
const char* label_of(Kind kind);  // the legend's words

// Height above ground shown from 0 (dark violet) to kRampTop metres (yellow), viridis;
// below 0 as 0, above the top as the top.
inline constexpr double kRampTop = 3.0;
Rgb height_colour(double height);

struct Shape {
  Ring ring;  // tile coordinates
  Kind kind;
};

// What read_footprints found: the shapes in drawing order, what the documents hold (for the
// legend), and the rejected candidates it could not draw (no index to take a footprint from).
struct Footprints {
  std::vector<Shape> shapes;
  bool truth = false;                  // true footprints given
  bool scored = false;                 // detections coloured by the score's outcome
  int undrawn = 0;                     // rejected candidates without a footprint
  std::map<std::string, int> reasons;  // Kind::rejected candidates by reason ("not given" when absent)
  // The documents as given and the tile the detections record ("" when absent), for check_tile.
  std::string detections_file, truth_file, detections_tile;
};

// The image bound: at most kMaxSide pixels along a side and kMaxPixels in all (map and
// legend; about 11 bytes a pixel are held while drawing, so ≤ 185 MB besides the points).
inline constexpr int kMaxSide = 8192;
inline constexpr long long kMaxPixels = 4096LL * 4096;

struct Image {
  int width = 0, height = 0;          // the whole picture: the map, the legend on its right
  int map_width = 0, map_height = 0;  // the map: pixels [0, map_width) x [0, map_height)
  std::vector<std::uint8_t> rgb;      // row-major from the top (north) row, 3 bytes a pixel
  double x0 = 0, y1 = 0, pixel = 1;   // map: x of the left edge, y of the top edge, metres a map pixel
  double data_pixel = 1;              // metres a data pixel (one height value)
  // The data pixels' grid: anchored at (grid_x0, grid_y1), the points' top-left corner, which is
  // the corner of data pixel (grid_col, grid_row) (whole data pixels added for footprints).
  double grid_x0 = 0, grid_y1 = 0;
  int grid_col = 0, grid_row = 0;
  int zoom = 1;        // map pixels a data pixel (one height value) along a side
  double density = 0;  // points per m² over the occupied 1 m cells
  // The scale bar: `bar_metres` long, pixels [bar_col, bar_col + bar_pixels) of row bar_row.
  double bar_metres = 0;
  int bar_col = 0, bar_row = 0, bar_pixels = 0;
  Rgb at(int col, int row) const {
    const std::size_t i = 3 * (static_cast<std::size_t>(row) * width + col);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

struct Params {
  int size = 0;      // pixels along the longer side of the map, [16, 8192]; 0: from --pixel or the density
  double pixel = 0;  // metres a data pixel, [0.005, 100]; 0: from --size or the density
  // This tile's index in the score's tiles, >= 0; -1: the tile whose "detections" is the
  // detections file as given (issue 30: not make's order), else the only tile of the score.
  int tile = -1;
  bool legend = true;  // false: the map alone, no legend nor scale bar (pictures side by side in a grid)
};

// Throws common::UsageError naming the option: --size 0 or in [16, 8192], --pixel 0 or in
// [0.005, 100] m, not both, --tile >= -1.
void validate(const Params& params);

// The documents whose footprints are drawn (paths; empty = not given; a score needs the truth).
struct Sources {
  std::string detections;  // canopy.detections v1 or v2
  std::string truth;       // canopy.scene_truth v1: true footprints
  std::string score;       // canopy.scene_score v1: colours by outcome
  std::string index;       // canopy.candidates v1 or v2; empty: the one the detections name
};

// Reads the documents: the true footprints first (truth, or missed when the score says the
// tile's vehicle was missed), then the rejected candidates by reason (none, failed, rejected)
// with their footprints from the candidates index, then the detections (model or cls by
// "level" — a v1 detection is at model level — or with a score right, wrong, false_alarm by
// the candidate's outcome). The index is `sources.index`, else the path the detections name
// as written, else that path from the detections' directory; when there is none (or no path)
// the rejected candidates are counted in `undrawn` with a warning. DataError naming the file
// and the member: not JSON, another format, a version other than 1 (2 for the detections),
// no "detections" / "vehicles" / "tiles" / "matches" array, no tile `tile` in the score (with
// tile -1: no tile or two whose "detections" is `sources.detections` in a score of several), a
// detection without a string "candidate", a "level" other than model or class, a rejected
// entry without a string "candidate" or with a "reason" not a string, a vehicle without an
// integer "instance" >= 0, a match without "tile" (an index of "tiles") or "outcome" (right,
// wrong, false_alarm, missed), a missed match without "instance", another match without a
// string "candidate", a footprint that is not a polygon of 3-64 [x, y] corners, an index
// without the rejected candidate or without its finite "centre", "length", "width", "heading".
Footprints read_footprints(const Sources& sources, int tile);

// Metres around the tile's points within which a document's footprints must reach (check_tile).
inline constexpr double kTileMargin = 10;

// The box {x0, y0, x1, y1} of the finite points of `scan`; nullopt when there is none.
std::optional<std::array<double, 4>> points_box(const formats::PointCloud& scan);

// Documents of another tile (docs/decisions/topview.md, stop 70): DataError naming the document
// and `tile` (the -i scan or the --raster, as given) with both extents and the tile the
// detections record, when the detections (their detections' and rejected candidates'
// footprints) or the truth (its vehicles') have footprints but none whose box comes within
// kTileMargin of `box` (the tile's points: points_box, or the raster's box). Some but not all
// of a document's footprints beyond that: a warning (they are drawn; the map widens to hold them).
void check_tile(const Footprints& footprints, const std::string& tile, const std::array<double, 4>& box);

// The picture, validate()d first. The data pixel (one height value): --pixel; else the box
// holding the points and shapes over --size; else from the density d (points per m² over
// occupied 1 m cells): sqrt(2 / d) rounded to 0.01 m (about two points a pixel), in
// [0.01, 2] m. Without --size each data pixel is drawn as zoom x zoom map pixels, the zoom
// making the map's longer side about 1000 pixels (1 to 8), so that outlines stay thin beside
// the cars. Beyond the bound the zoom is lowered, then an automatic data pixel coarsened; a
// given --pixel or --size beyond it: UsageError. Non-finite points are skipped.
// Ground: the lowest point per 1 m cell, opened (a min then a max filter over 13 x 13 cells:
// objects narrower than 13 m go, slopes stay), bilinear over the cells that have a value; a
// data pixel's height is that of its highest point above the ground; empty data pixels take
// the mean of their filled neighbours (spacing / pixel passes, 2 to 8).
Image render(const formats::PointCloud& scan, const Footprints& footprints, const Params& params);

// The heights of render() before the gaps are filled, from the points alone (no footprint):
// the data pixel and grid render() picks when no footprint reaches beyond the points' box
// (--pixel / --size as there), the data pixels' highest height above ground (NaN: no point),
// the points' box and density (topview --raster-out; docs/decisions/topview.md "A raster
// for the tile workflow"). Error when there is no finite point.
formats::HeightRaster raster(const formats::PointCloud& scan, const Params& params);
// The picture from such a raster: the same as render() on its points when every footprint
// lies within the points' box and the zoom is the same (the same bytes: tested). A footprint
// beyond widens the map as render() does, and each raster pixel goes to the data pixel that
// holds its centre. --pixel / --size: UsageError (the raster's); beyond the bound: Error.
Image render(const formats::HeightRaster& raster, const Footprints& footprints, const Params& params);

// The legend (drawn by render into the panel right of the map); exposed for the tests.
// Its text lines, top to bottom, as drawn into IMG's panel: "pixel ..." is the data pixel (one
// height value, --pixel), not the map pixel it is zoomed to.
std::vector<std::string> legend_text(const Footprints& footprints, const Image& img);
bool glyph_ink(char c, int col, int row);  // the 5 x 7 font (9 rows with descenders): ink at (col, row)?
inline constexpr int kGlyphWidth = 5, kGlyphHeight = 9;

// The PNG file of the picture. fast: libpng's PNG_IMAGE_FLAG_FAST (no filter search, a quicker
// deflate; on the 1 ha scene tile's 4263 x 3335 picture 7x quicker and 5% smaller); false:
// libpng's defaults, the encoding before (docs/decisions/topview.md §11). The same pixels.
std::string encode_png(const Image& image, bool fast = true);

}  // namespace canopy::topview
