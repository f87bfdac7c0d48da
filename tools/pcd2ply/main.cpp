// pcd2ply: the CLI binding of the stage (pcd2ply.h).
#include <string>

#include "canopy/common/cli.h"
#include "canopy/common/log.h"
#include "canopy/formats/points_io.h"
#include "pcd2ply/pcd2ply.h"

int main(int argc, char** argv) {
  namespace cm = canopy::common;
  namespace fm = canopy::formats;
  cm::Tool tool("pcd2ply", "Convert a PCD point cloud to a PLY point set (all fields kept).");
  tool.without_threads();
  canopy::pcd2ply::Params p;
  std::string input = "-", output = "-";
  tool.add_input(&input, "point cloud: PCD, LAS or PLY point set");
  tool.add_output(&output, "PLY point set");
  tool.add_flag("--ascii", &p.ascii, "write ascii PLY instead of binary little endian");
  return tool.run(argc, argv, [&] {
    canopy::pcd2ply::validate(p);
    cm::log::Phase phase("convert");
    const fm::Mesh mesh = canopy::pcd2ply::run(
        p, {fm::read_points(input, "pcd2ply"), {"pcd2ply", CANOPY_VERSION, tool.parameters(), {input}}});
    fm::write_ply(mesh, output, p.ascii);
    phase.done(std::to_string(mesh.vertices.size()) + " points, " +
               std::to_string(mesh.vertices.names().size()) + " fields");
  });
}
