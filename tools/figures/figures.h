// figures: the experiment's pictures, rendered with VTK to PNG (issue 8, "Pictures").
//   render_mesh  - a segmentation PLY (per-vertex red/green/blue) shaded, from a fixed oblique
//                  viewpoint, so that every cell of a grid uses the same camera;
//   tile_grid    - PNG tiles in a labelled grid (rows objects, columns noise levels; thesis
//                  Figs. 5.11-5.13), a missing tile drawn as an empty cell marked "failed";
//   plot_scores  - score of the correct model against noise, one panel per scene, one line
//                  per object.
// render_mesh and plot_scores draw with OpenGL through VTK's X11 render window: they need an
// X display (run under `xvfb-run -a` on a headless machine; require_display() checks first).
// tile_grid and the PNG/CSV I/O do not. VTK stays inside the .cpp files.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "canopy/formats/ply.h"

namespace canopy::figures {

// 8-bit RGB image, rows top to bottom (PNG order), pixel (x, y) at rgb[3 * (y * width + x)].
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;

  Image() = default;
  Image(int w, int h, std::array<std::uint8_t, 3> fill = {255, 255, 255});
  std::uint8_t* at(int x, int y) { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
  const std::uint8_t* at(int x, int y) const { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
};

// ---- mesh ---------------------------------------------------------------------------------
enum class Framing {
  kBox,     // the fixed box `box` (centred on the origin in x and y, from the ground z = 0 up):
            // the same camera for every mesh, so the cells of a grid are comparable
  kBounds,  // the mesh's own bounding box
};

struct MeshView {
  int width = 640;
  int height = 480;
  double elevation_deg = 35;  // camera above the ground plane
  double azimuth_deg = 35;    // from +x (the vehicle's front) toward +y (its left side)
  Framing framing = Framing::kBox;
  std::array<double, 3> box{10, 4, 4};  // length (x), width (y), height (z) in metres
  std::array<std::uint8_t, 3> background{255, 255, 255};
  std::array<std::uint8_t, 3> default_colour{200, 200, 200};  // when the PLY has no colours
};

// Throws common::UsageError naming the option: --width/--height within [16, 8192] pixels,
// --elevation within (-90, 90) degrees, --box-length/--box-width/--box-height positive.
void validate(const MeshView& view);

// Renders the mesh shaded (smooth normals, two-sided light) with a parallel projection.
// Each face takes the colour most of its three vertices have (ties: its first vertex), so
// segment boundaries stay sharp instead of blending. Throws DataError(name) for a mesh
// without faces, Error when no display is available.
Image render_mesh(const formats::Mesh& mesh, const MeshView& view, const std::string& name);

// ---- grid ---------------------------------------------------------------------------------
struct GridParams {
  int cols = 1;
  std::vector<std::string> row_labels;  // empty, or one per row (rows = ceil(cells / cols))
  std::vector<std::string> col_labels;  // empty, or one per column
  std::string title;                    // optional line above the grid
  int gap = 4;                          // pixels between cells
  int font_size = 18;                   // label text size (points at 72 dpi = pixels)
  // Crop every tile to the union, over all present tiles, of the boxes holding pixels that
  // differ from the tile's top-left (background) pixel, plus `margin` pixels. One crop for
  // all tiles keeps the common camera of mesh renders comparable across cells.
  bool trim = true;
  int margin = 8;
};

// Throws common::UsageError naming the option: --cols >= 1, --font-size 4..200, --gap and
// --margin 0..1000.
void validate(const GridParams& params);

// Tiles cells row by row. Every cell has the size of the first present image after trimming
// (a differently sized tile is centred and clipped or padded); std::nullopt is drawn as a light grey cell
// marked "failed". Throws UsageError for a label count that does not match, Error when no
// cell is present.
Image tile_grid(const std::vector<std::optional<Image>>& cells, const GridParams& params);

// ---- plot ---------------------------------------------------------------------------------
// One row of the experiment's scores.csv (header: object,scene,noise_mm,score,rank,entropy;
// column order free, extra columns ignored). A missing value (empty, "nan", "NA") is NaN
// for score/entropy and 0 for rank.
struct ScoreRow {
  std::string object;
  std::string scene;
  double noise_mm = 0;
  double score = 0;
  int rank = 0;
  double entropy = 0;
  // The y value's interval (plot --lo/--hi: drawn as a vertical bar); NaN when not read.
  double lo = std::numeric_limits<double>::quiet_NaN(), hi = std::numeric_limits<double>::quiet_NaN();
};

// Which columns are read into a ScoreRow (plot --x/--y/--series/--panel): x -> noise_mm,
// y -> score, series -> object, panel -> scene. The defaults read scores.csv. An empty panel
// column puts every row in one panel. With any column changed (strict = false), a row whose
// x is text (a summary row such as "all") is left out instead of being an error, so the
// scene experiment's tables (results/scenes/summary.csv, cover_bins.csv) plot as they are.
struct PlotColumns {
  std::string x = "noise_mm";
  std::string y = "score";
  std::string series = "object";
  std::string panel = "scene";
  std::string lo, hi;  // columns of the y value's interval ("" = none): a bar per point
  bool strict = true;
};

std::vector<ScoreRow> parse_scores_csv(const std::string& text, const std::string& name,
                                       const PlotColumns& columns = PlotColumns{});

struct PlotParams {
  int width = 1200;
  int height = 420;
  std::string y_title = "score of the correct model";  // e.g. "share of the visible area" for areas.csv
  std::string x_title = "noise (mm)";
  std::string title;  // panel title; "" = "scene: <panel>"
};

// Throws common::UsageError naming --width/--height unless both are within [16, 8192] pixels.
void validate(const PlotParams& params);

// One panel per scene (in order of first appearance), one line per object (same colour in
// every panel), x: the distinct noise levels at equal spacing labelled in mm, y: score 0..1
// (extended if a score exceeds 1). Cases whose correct model is not ranked first are marked
// with a black cross. Rows with a NaN score are left out. Throws DataError(name) when no
// row has a score, Error when no display is available.
// The colour of series i (plot_scores' lines): a fixed table of 16 distinct colours, then
// generated hues; no fixed number of series (models, classes) is assumed.
std::array<std::uint8_t, 3> series_colour(std::size_t i);

Image plot_scores(const std::vector<ScoreRow>& rows, const PlotParams& params, const std::string& name);

// ---- I/O ----------------------------------------------------------------------------------
// Reads a PNG (grey, grey+alpha, RGB or RGBA; alpha composited over white). Throws DataError.
Image read_png(const std::string& path);
// PNG bytes of the image (deterministic: no time stamp).
std::string encode_png(const Image& image);
// Writes atomically (temporary file in the same directory, renamed into place).
void write_png(const Image& image, const std::string& path);

// Throws Error("no X display ...") unless an X display can be opened: VTK 9.1 as Debian
// builds it renders through X11/GLX only and aborts without a display.
void require_display();

}  // namespace canopy::figures
