#include "pcd2ply/pcd2ply.h"

#include <string>
#include <utility>
#include <vector>

#include "canopy/common/error.h"

namespace canopy::pcd2ply {
namespace {

std::string field_list(const formats::PointCloud& cloud) {
  std::string out;
  for (const auto& n : cloud.names()) out += (out.empty() ? "" : " ") + n;
  return out;
}

}  // namespace

Outputs run(const Params&, const Inputs& inputs) {
  const formats::PointCloud& cloud = inputs.cloud;
  const formats::Provenance& provenance = inputs.provenance;
  // canopy's PLY reader needs x y z: a PLY without them could not be read back.
  const std::string name = provenance.inputs.empty() ? "input" : common::display_name(provenance.inputs[0]);
  cloud.require({"x", "y", "z"}, name, "a PLY point set needs x, y, z; the fields are " + field_list(cloud));
  formats::Mesh mesh;
  mesh.vertices = cloud;
  const std::vector<std::string> lines = formats::provenance_comments(provenance);
  mesh.vertices.comments.insert(mesh.vertices.comments.end(), lines.begin(), lines.end());
  return mesh;
}

}  // namespace canopy::pcd2ply
