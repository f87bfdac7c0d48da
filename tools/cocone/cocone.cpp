// run(): samples -> mesh (Cocone, then the thesis post-processing).
#include <numeric>
#include <string>

#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "canopy/formats/cloud_eigen.h"
#include "cocone/cocone.h"

namespace canopy::cocone {

void validate(const Params& p) {
  const double deg = common::kDegree;
  if (!(p.cocone.cocone_angle > 0 && p.cocone.cocone_angle < 90 * deg))
    throw common::UsageError("--cocone-angle must be in (0, 90) deg");
  if (!(p.cocone.flat_ratio > 0)) throw common::UsageError("--flat-ratio must be > 0");
  if (!(p.cocone.flat_angle > 0 && p.cocone.flat_angle <= 90 * deg))
    throw common::UsageError("--flat-angle must be in (0, 90] deg");
  if (!(p.cocone.sharp_angle > 0 && p.cocone.sharp_angle <= 180 * deg))
    throw common::UsageError("--sharp-angle must be in (0, 180] deg");
  if (!(p.post.min_height >= 0) || !(p.post.max_area >= 0) || !(p.post.max_aspect >= 0)) {
    throw common::UsageError("--min-height, --max-area and --max-aspect must be >= 0");
  }
  if (p.post.max_aspect > 0 && p.post.max_aspect < 1)
    throw common::UsageError("--max-aspect below 1 removes every facet");
}

Outputs run(const Params& params, const Inputs& inputs) {
  const formats::PointCloud& samples = *inputs.samples;
  const std::vector<Eigen::Vector3d> points = formats::to_vectors(samples);
  std::vector<Eigen::Vector3d> normals;
  if (formats::has_fields(samples, formats::kNormalFields)) {
    normals = formats::to_vectors(samples, formats::kNormalFields);
  }
  const Surface surface = reconstruct(points, normals, params.cocone);
  const ReconstructStats& s = surface.stats;
  common::log::info("surface: " + std::to_string(s.faces) + " triangles, " + std::to_string(s.components) +
                    " components, " + std::to_string(s.boundary_edges) + " boundary edges" +
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
               std::to_string(p.large_facets) + " large facets, " + std::to_string(p.sliver_facets) +
               " high-aspect facets, " + std::to_string(p.orphan_vertices) + " orphan vertices; " +
               std::to_string(post.faces.size()) + " triangles on " + std::to_string(post.kept.size()) +
               " vertices left");
    mesh.vertices = samples.select(post.kept);
    mesh.faces = post.faces;
  }
  if (mesh.faces.empty() && s.faces == 0) {
    // Cocone itself made none (review F14, stop 71: the message blamed post-processing): too few or
    // too sparse samples, e.g. fitvox's few voxels on a sparse candidate.
    throw common::Error("Cocone made no triangle from " + std::to_string(samples.size()) +
                        " samples: too few or too sparse samples for a surface");
  }
  if (mesh.faces.empty()) {
    throw common::Error("the mesh has no triangle left (" + std::to_string(s.faces) + " from Cocone" +
                        (params.postprocess
                             ? ", all removed by post-processing; check the minimum height and that "
                               "coordinates are metres with the ground at z = 0)"
                             : "; are the samples a sampled surface?)"));
  }
  return mesh;
}

}  // namespace canopy::cocone
