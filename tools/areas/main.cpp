// areas: the target's surface area at each stage of one trial, as areas.json (issue 19).
#include <string>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/cli.h"
#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/ply.h"
#include "areas/areas.h"

using namespace canopy;

int main(int argc, char** argv) {
  common::Tool tool("areas",
                    "Target surface area at each stage of a trial: visible (labelled scan), "
                    "fitvox samples, cocone mesh, ncut segments, gmatch's largest segments.");
  std::string scan, samples, mesh, segments, out = "-";
  tool.without_threads();
  areas::Params a;
  tool.add("--scan", &scan, "labelled noise-free scan PCD (the visible surface)")->required();
  tool.add("--samples", &samples, "fitvox samples PCD")->required();
  tool.add("--mesh", &mesh, "cocone mesh PLY")->required();
  tool.add("--segments", &segments, "ncut segment graph JSON")->required();
  tool.add_output(&out, "areas JSON");
  tool.add_length("--spacing", &a.spacing, "the scan's pixel spacing (rangetrace --spacing), 1mm to 10m");
  tool.add_length("--cell", &a.cell,
                  "lattice cell of the visible-area estimate (normals, view overlap), 1 to 4 x --spacing");
  tool.add_length("--voxel", &a.voxel, "fitvox's voxel edge (each sample stands for its voxel), 1mm to 100m");
  tool.add("--max-segments", &a.max_segments, "gmatch's X: largest segments matched");
  return tool.run(argc, argv, [&] {
    areas::validate(a);
    common::log::Phase phase("areas");
    areas::Inputs in;
    in.scan = formats::read_pcd(scan);
    in.scan_name = common::display_name(scan);
    in.samples = formats::read_pcd(samples);
    in.samples_name = common::display_name(samples);
    in.mesh = formats::read_ply(mesh);
    in.mesh_name = common::display_name(mesh);
    in.segments = documents::read_segment_graph(segments);
    in.segments_name = common::display_name(segments);
    const areas::Areas r = areas::run(a, in);
    common::write_file_atomic(out, documents::write_areas(r, {scan, samples, mesh, segments}));
    char buf[200];
    std::snprintf(buf, sizeof buf, "visible %.2f, samples %.2f, mesh %.2f, segments %.2f, largest %d %.2f m2",
                  r.visible, r.samples, r.mesh, r.segments, r.max_segments, r.matched);
    phase.done(buf);
  });
}
