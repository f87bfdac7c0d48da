// cocone: surface reconstruction of fitvox samples (Cocone + thesis §4.5 post-processing).
#include <string>

#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/points_io.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/provenance.h"
#include "cocone/cocone.h"

namespace cm = canopy::common;
namespace cc = canopy::cocone;

int main(int argc, char** argv) {
  cm::Tool tool("cocone",
                "Surface reconstruction of a sample PCD (thesis ch. 4): Cocone with "
                "Dey-Giesen boundary detection, then the thesis mesh post-processing. "
                "Writes a PLY mesh whose vertices are the surviving sample rows.");
  tool.without_threads();
  cc::Params p;
  std::string in = "-", out = "-";
  bool raw = false, no_boundary = false, keep_orphans = false;
  tool.add_input(&in, "samples: PCD, PLY point set or LAS (fitvox output; needs x y z)");
  tool.add_output(&out, "mesh PLY");
  tool.add_angle("--cocone-angle", &p.cocone.cocone_angle,
                 "cocone half-width around the tangent plane (0,90)");
  tool.add_flag("--no-boundary-detection", &no_boundary,
                "plain Cocone: every sample constrains its triangles (closed, dense surfaces only)");
  tool.add("--flat-ratio", &p.cocone.flat_ratio,
           "Dey-Giesen ratio: flat needs co-polygon width <= this x pole height (>0)");
  tool.add_angle("--flat-angle", &p.cocone.flat_angle, "Dey-Giesen max angle between neighbour poles (0,90]");
  tool.add_angle("--sharp-angle", &p.cocone.sharp_angle, "max normal turn between umbrella triangles (0,180]");
  tool.add_flag("--no-postprocess", &raw, "write the raw Cocone mesh (every sample row, no pruning)");
  tool.add_length("--min-height", &p.post.min_height, "step 1: remove vertices below this z (0 = off)");
  tool.add("--max-area", &p.post.max_area, "step 3: remove facets with area >= this, m^2 (0 = off)");
  tool.add("--max-aspect", &p.post.max_aspect,
           "step 4: remove facets with longest/shortest edge > this (0 = off)");
  tool.add_flag("--keep-orphans", &keep_orphans, "skip step 5 (keep vertices in no facet)");

  return tool.run(argc, argv, [&] {
    p.postprocess = !raw;
    p.cocone.boundary_detection = !no_boundary;
    p.post.remove_orphans = !keep_orphans;
    cc::validate(p);

    const canopy::formats::PointCloud samples = canopy::formats::read_points(in, "cocone");
    samples.require({"x", "y", "z"}, cm::display_name(in), "is this a canopy samples PCD?");
    // fitvox's samples carry a normal and the fit of each voxel; a raw scan does not.
    std::string missing;
    for (const char* f : {"normal_x", "normal_y", "normal_z", "point_count", "rms"}) {
      if (!samples.has(f)) missing += std::string(missing.empty() ? "" : " ") + f;
    }
    if (!missing.empty()) {
      cm::log::warn(cm::display_name(in) + ": no " + missing +
                    " fields: these are not fitvox "
                    "samples (a raw scan? run it through fitvox first: scan -> fitvox -> cocone)");
    }
    canopy::formats::Mesh mesh;
    try {
      mesh = cc::run(p, {&samples});
    } catch (const cm::DataError&) { throw; } catch (const cm::Error& e) {
      throw cm::DataError(cm::display_name(in), e.what());
    }
    mesh.vertices.comments =
        canopy::formats::provenance_comments({"cocone", CANOPY_VERSION, tool.parameters(), {in}});
    canopy::formats::write_ply(mesh, out);
    cm::log::info("wrote " + std::to_string(mesh.faces.size()) + " triangles on " +
                  std::to_string(mesh.vertices.size()) + " of " + std::to_string(samples.size()) +
                  " samples to " + cm::display_name(out, true));
  });
}
