// topview: tile scan + detections.json [+ truth.json [+ score.json]] -> a PNG from straight
// above with the footprints outlined (right, wrong, false alarm, missed in their colours).
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
                    "A tile from straight above (highest point per pixel, grey by height) with the "
                    "footprints of the detections and, if given, of the true vehicles, coloured by "
                    "the score's outcome: right green, wrong model orange, false alarm magenta, "
                    "missed yellow.");
  tool.without_threads();
  topview::Params p;
  topview::Sources src;
  std::string in, out;
  tool.add_input(&in, "the tile scan (PCD, PLY or LAS with x y z)");
  tool.add_output(&out, "PNG");
  tool.add("--detections", &src.detections, "detections.json (canopy.detections v1)");
  tool.add("--truth", &src.truth, "truth.json (canopy.scene_truth v1): true footprints");
  tool.add("--score", &src.score, "score.json (canopy.scene_score v1): colours by outcome");
  tool.add("--tile", &p.tile, "this tile's index in the score's tiles");
  tool.add("--size", &p.size, "pixels along the longer side");
  return tool.run(argc, argv, [&] {
    if (in.empty() || in == "-" || out.empty() || out == "-")
      throw common::UsageError("-i and -o must name files");
    if (src.detections.empty()) throw common::UsageError("--detections is required");
    topview::validate(p);
    if (!src.score.empty() && src.truth.empty()) throw common::UsageError("--score needs --truth");
    common::check_output(out);
    const std::vector<topview::Shape> shapes = topview::read_footprints(src, p.tile);
    const formats::PointCloud scan = formats::read_points(in, "topview");
    scan.require({"x", "y", "z"}, common::display_name(in), "is this a point cloud?");
    const topview::Image img = topview::run(scan, shapes, p);
    common::write_file_atomic(out, topview::encode_png(img));
    common::log::info(std::to_string(img.width) + " x " + std::to_string(img.height) + " pixels, " +
                      std::to_string(img.pixel * 1000).substr(0, 6) + " mm a pixel, " +
                      std::to_string(shapes.size()) + " footprints");
  });
}
