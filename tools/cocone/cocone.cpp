// run(): samples -> mesh (Cocone, then the thesis post-processing).
#include <numeric>
#include <string>

#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "cocone/cocone.h"

namespace canopy::cocone {

formats::Mesh run(const formats::PointCloud& samples, const Params& params) {
  const std::size_t n = samples.size();
  const auto& x = samples.col("x");
  const auto& y = samples.col("y");
  const auto& z = samples.col("z");
  std::vector<Eigen::Vector3d> points(n);
  for (std::size_t i = 0; i < n; ++i) points[i] = Eigen::Vector3d(x[i], y[i], z[i]);
  std::vector<Eigen::Vector3d> normals;
  if (samples.has("normal_x") && samples.has("normal_y") && samples.has("normal_z")) {
    const auto& nx = samples.col("normal_x");
    const auto& ny = samples.col("normal_y");
    const auto& nz = samples.col("normal_z");
    normals.resize(n);
    for (std::size_t i = 0; i < n; ++i) normals[i] = Eigen::Vector3d(nx[i], ny[i], nz[i]);
  }
  const Surface surface = reconstruct(points, normals, params.cocone);
  const ReconstructStats& s = surface.stats;
  common::log::info("surface: " + std::to_string(s.faces) + " triangles, " +
                    std::to_string(s.components) + " components, " +
                    std::to_string(s.boundary_edges) + " boundary edges" +
                    (s.nonmanifold_dropped ? ", " + std::to_string(s.nonmanifold_dropped) +
                                                 " triangles dropped at non-manifold edges"
                                           : ""));
  formats::Mesh mesh;
  if (!params.postprocess) {
    mesh.vertices = samples;
    mesh.faces = surface.faces;
  } else {
    common::log::Phase phase("postprocess");
    const PostResult post = postprocess(points, surface.faces, params.post);
    const PostStats& p = post.stats;
    phase.done("removed " + std::to_string(p.low_vertices) + " low vertices, " +
               std::to_string(p.partial_facets) + " facets with < 3 vertices, " +
               std::to_string(p.large_facets) + " large facets, " +
               std::to_string(p.sliver_facets) + " high-aspect facets, " +
               std::to_string(p.orphan_vertices) + " orphan vertices; " +
               std::to_string(post.faces.size()) + " triangles on " +
               std::to_string(post.kept.size()) + " vertices left");
    mesh.vertices = samples.select(post.kept);
    mesh.faces = post.faces;
  }
  if (mesh.faces.empty()) {
    throw common::Error(
        "the mesh has no triangle left (" + std::to_string(s.faces) + " from Cocone" +
        (params.postprocess ? ", all removed by post-processing; check --min-height and that "
                              "coordinates are metres with the ground at z = 0)"
                            : "; are the samples a sampled surface?)"));
  }
  return mesh;
}

}  // namespace canopy::cocone
