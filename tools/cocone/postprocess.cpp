// Thesis §4.5 mesh post-processing, in the thesis order:
//   1. vertices lower than min_height above the ground plane z = 0,
//   2. facets left with fewer than three vertices,
//   3. facets of area >= max_area,
//   4. facets whose aspect ratio (longest / shortest edge) > max_aspect,
//   5. vertices that belong to no facet.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "canopy/common/error.h"
#include "cocone/cocone.h"

namespace canopy::cocone {

PostResult postprocess(const std::vector<Eigen::Vector3d>& points, const std::vector<Face>& faces,
                       const PostParams& params) {
  const std::size_t n = points.size();
  PostResult out;
  std::vector<std::uint8_t> removed(n, 0);
  if (params.min_height > 0) {
    for (std::size_t v = 0; v < n; ++v) {
      if (points[v].z() < params.min_height) {
        removed[v] = 1;
        ++out.stats.low_vertices;
      }
    }
  }
  std::vector<Face> kept_faces;
  kept_faces.reserve(faces.size());
  for (const Face& f : faces) {
    for (int v : f) {
      if (v < 0 || static_cast<std::size_t>(v) >= n) {
        throw common::Error("internal: face index " + std::to_string(v) + " out of range");
      }
    }
    if (removed[f[0]] || removed[f[1]] || removed[f[2]]) {
      ++out.stats.partial_facets;
      continue;
    }
    const Eigen::Vector3d& a = points[f[0]];
    const Eigen::Vector3d& b = points[f[1]];
    const Eigen::Vector3d& c = points[f[2]];
    if (params.max_area > 0 && 0.5 * (b - a).cross(c - a).norm() >= params.max_area) {
      ++out.stats.large_facets;
      continue;
    }
    if (params.max_aspect > 0) {
      const double e0 = (b - a).norm(), e1 = (c - b).norm(), e2 = (a - c).norm();
      const double lo = std::min({e0, e1, e2}), hi = std::max({e0, e1, e2});
      // A zero-length edge is an infinite aspect ratio.
      if (!(lo > 0) || hi / lo > params.max_aspect) {
        ++out.stats.sliver_facets;
        continue;
      }
    }
    kept_faces.push_back(f);
  }
  std::vector<std::uint8_t> used(n, 0);
  for (const Face& f : kept_faces)
    for (int v : f) used[v] = 1;
  std::vector<std::int32_t> new_index(n, -1);
  for (std::size_t v = 0; v < n; ++v) {
    if (removed[v]) continue;
    if (params.remove_orphans && !used[v]) {
      ++out.stats.orphan_vertices;
      continue;
    }
    new_index[v] = static_cast<std::int32_t>(out.kept.size());
    out.kept.push_back(v);
  }
  out.faces.reserve(kept_faces.size());
  for (const Face& f : kept_faces) out.faces.push_back({new_index[f[0]], new_index[f[1]], new_index[f[2]]});
  return out;
}

}  // namespace canopy::cocone
