#include "pcd2ply/pcd2ply.h"

#include <string>
#include <utility>
#include <vector>

namespace canopy::pcd2ply {

formats::Mesh run(formats::PointCloud cloud, const formats::Provenance& provenance) {
  formats::Mesh mesh;
  mesh.vertices = std::move(cloud);
  const std::vector<std::string> lines = formats::provenance_comments(provenance);
  mesh.vertices.comments.insert(mesh.vertices.comments.end(), lines.begin(), lines.end());
  return mesh;
}

}  // namespace canopy::pcd2ply
