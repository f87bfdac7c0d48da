// topview: tile scan + detections.json [+ truth.json [+ score.json]] -> a PNG from straight
// above, north up: height above ground as a shaded colour ramp, the candidates outlined by
// outcome, the true footprints, a legend and a scale bar (docs/decisions/topview.md).
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/points_io.h"
#include "topview/topview.h"

using namespace canopy;

int main(int argc, char** argv) {
  common::Tool tool("topview",
                    "A tile from straight above, north up: the height above ground of the highest "
                    "point per pixel as a colour ramp (0-3 m) shaded by the relief, the candidates "
                    "outlined by outcome (found at model level green, at class level blue, none "
                    "violet, rejected pink, failed red; with a score right green, wrong answer "
                    "orange, false alarm magenta), true vehicles white (missed yellow), and a "
                    "legend with counts, a scale bar in metres and the pixel size.");
  tool.without_threads();
  topview::Params p;
  topview::Sources src;
  std::string in, out;
  tool.add_input(&in, "the tile scan (PCD, PLY, LAS or LAZ with x y z)");
  tool.add_output(&out, "PNG");
  std::string raster_in, raster_out;
  tool.add("--raster", &raster_in,
           "draw from this height raster (canopy.height_raster, topview --raster-out) instead of -i: "
           "the same picture when no footprint reaches beyond the tile's points (docs/decisions/topview.md, "
           "\"A raster for the tile workflow\")");
  tool.add_output(
      "--raster-out", &raster_out,
      "write the tile's height raster (formats/README.md, \"Height raster\") to this file instead of a "
      "picture: -i and --pixel / --size only");
  tool.add(
      "--detections", &src.detections,
      "detections.json (canopy.detections v1 or v2); required (a picture draws a tile's detections), but "
      "with --raster-out");
  tool.add("--index", &src.index,
           "candidates index.json (canopy.candidates): the rejected candidates' footprints; default: the "
           "one the detections name");
  tool.add("--truth", &src.truth, "truth.json (canopy.scene_truth v1): true footprints");
  tool.add("--score", &src.score, "score.json (canopy.scene_score v1): colours by outcome");
  tool.add("--tile", &p.tile,
           "this tile's index in the score's tiles; default: the tile whose detections is --detections "
           "as given, else the score's only tile")
      ->default_str("");
  tool.add("--size", &p.size, "pixels along the longer side of the map (0: from --pixel or the density)");
  bool no_legend = false;
  tool.add_flag("--no-legend", &no_legend,
                "the map alone: no legend, no scale bar (pictures side by side in a grid)");
  tool.add_length("--pixel", &p.pixel,
                  "metres a data pixel, one height value, drawn zoomed to about 1000 map pixels (0: from "
                  "--size or the density, about 2 points a pixel)");
  std::string png = "fast";
  tool.add("--png", &png,
           "fast or default: the PNG encoder's setting (the same pixels; fast: libpng's "
           "PNG_IMAGE_FLAG_FAST, default: libpng's defaults, the encoding before, "
           "docs/decisions/topview.md §11)");
  return tool.run(argc, argv, [&] {
    if (png != "fast" && png != "default") throw common::UsageError("--png must be fast or default");
    if (!raster_out.empty()) {  // the raster of the tile, no picture
      if (in.empty() || in == "-" || raster_out == "-")
        throw common::UsageError("-i and --raster-out must name files");
      if (!(out.empty() || out == "-") || !raster_in.empty() || !src.detections.empty() ||
          !src.truth.empty() || !src.score.empty() || !src.index.empty())
        throw common::UsageError("--raster-out takes -i and --pixel / --size only");
      topview::validate(p);
      common::check_output(raster_out);
      const formats::PointCloud scan =
          formats::read_points(in, "topview", formats::FieldSelection::only({"x", "y", "z"}));
      scan.require({"x", "y", "z"}, common::display_name(in), "is this a point cloud?");
      const formats::HeightRaster r = topview::raster(scan, p);
      formats::write_height_raster(r, raster_out);
      common::log::info(std::to_string(r.width) + " x " + std::to_string(r.height) + " data pixels, " +
                        std::to_string(r.pixel * 1000).substr(0, 6) + " mm a pixel, " +
                        std::to_string(r.density).substr(0, 6) + " points/m2");
      return;
    }
    const bool from_raster = !raster_in.empty();
    if (from_raster && !(in.empty() || in == "-")) throw common::UsageError("give -i or --raster, not both");
    if ((!from_raster && (in.empty() || in == "-")) || out.empty() || out == "-")
      throw common::UsageError("-i (or --raster) and -o must name files");
    if (src.detections.empty())
      throw common::UsageError(
          "--detections is required (collect's detections.json; a tile's heights alone: --raster-out)");
    p.legend = !no_legend;
    topview::validate(p);
    if (!src.score.empty() && src.truth.empty()) throw common::UsageError("--score needs --truth");
    common::check_output(out);
    const topview::Footprints footprints = topview::read_footprints(src, p.tile);
    topview::Image img;
    if (from_raster) {
      const formats::HeightRaster r = formats::read_height_raster(raster_in);
      topview::check_tile(footprints, raster_in, {r.box_x0, r.box_y0, r.box_x1, r.box_y1});
      img = topview::render(r, footprints, p);
    } else {
      // Only the coordinates: a tile's other fields are never made (issue 31).
      const formats::PointCloud scan =
          formats::read_points(in, "topview", formats::FieldSelection::only({"x", "y", "z"}));
      scan.require({"x", "y", "z"}, common::display_name(in), "is this a point cloud?");
      // Documents of another tile: refused, not drawn as a picture of both at a metre a pixel.
      if (const auto box = topview::points_box(scan)) topview::check_tile(footprints, in, *box);
      img = topview::render(scan, footprints, p);
    }
    common::write_file_atomic(out, topview::encode_png(img, png == "fast"));
    common::log::info(std::to_string(img.width) + " x " + std::to_string(img.height) + " pixels (map " +
                      std::to_string(img.map_width) + " x " + std::to_string(img.map_height) + "), " +
                      std::to_string(img.data_pixel * 1000).substr(0, 6) + " mm a data pixel drawn " +
                      std::to_string(img.zoom) + " x " + std::to_string(img.zoom) + ", " +
                      std::to_string(img.density).substr(0, 6) + " points/m2, " +
                      std::to_string(footprints.shapes.size()) + " footprints");
  });
}
