// pcd2ply: a PCD cloud as a PLY point set, every field kept as a vertex property, so scans
// and samples open in MeshLab and CloudCompare (MeshLab does not read PCD).
#include <string>
#include <vector>

#include "canopy/common/cli.h"
#include "canopy/common/log.h"
#include "canopy/formats/points_io.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/provenance.h"

int main(int argc, char** argv) {
  canopy::common::Tool tool("pcd2ply", "Convert a PCD point cloud to a PLY point set (all fields kept).");
  tool.without_threads();
  std::string input = "-", output = "-";
  bool ascii = false;
  tool.add_input(&input, "point cloud: PCD, LAS or PLY point set");
  tool.add_output(&output, "PLY point set");
  tool.add_flag("--ascii", &ascii, "write ascii PLY instead of binary little endian");
  return tool.run(argc, argv, [&] {
    canopy::common::log::Phase phase("convert");
    canopy::formats::Mesh mesh;
    mesh.vertices = canopy::formats::read_points(input, "pcd2ply");
    const std::vector<std::string> provenance =
        canopy::formats::provenance_comments({"pcd2ply", CANOPY_VERSION, tool.parameters(), {input}});
    mesh.vertices.comments.insert(mesh.vertices.comments.end(), provenance.begin(), provenance.end());
    canopy::formats::write_ply(mesh, output, ascii);
    phase.done(std::to_string(mesh.vertices.size()) + " points, " +
               std::to_string(mesh.vertices.names().size()) + " fields");
  });
}
