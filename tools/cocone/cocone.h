// cocone: surface reconstruction of fitvox samples (thesis chapter 4).
//
// reconstruct(): the Cocone algorithm (Amenta, Choi, Dey, Leekha) on a 3D Delaunay
// triangulation, with Dey–Giesen boundary/undersampling detection (bound-cocone candidate
// rule), umbrella-protected pruning and an orientation-consistent manifold walk
// (docs/decisions/cocone.md, shared spec ALGORITHMS.md §A).
// postprocess(): the thesis §4.5 mesh pruning, each rule with its own parameter.
// run(): samples PointCloud -> Mesh whose vertices are the surviving sample rows.
//
// Units: metres; world frame z up, ground plane z = 0. CGAL stays inside the .cpp files.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/math.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/point_cloud.h"

namespace canopy::cocone {

using Face = std::array<std::int32_t, 3>;

struct CoconeParams {
  double cocone_angle = common::kPi / 8;     // θ: half-width of the cocone band around the tangent plane
  bool boundary_detection = true;            // Dey–Giesen flatness + bound-cocone candidate rule
  double flat_ratio = 1.0 / 1.2;             // ρ: flat needs co-polygon width <= ρ · negative-pole height
  double flat_angle = common::kPi / 3;       // α: max angle between pole lines of cocone neighbours
  double sharp_angle = 2 * common::kPi / 3;  // max normal turn between adjacent umbrella triangles
};

struct PostParams {
  double min_height = 0.3;     // remove vertices with z below this (m); 0 = off
  double max_area = 0.04;      // remove facets with area >= this (m^2); 0 = off
  double max_aspect = 1.75;    // remove facets with longest/shortest edge > this; 0 = off
  bool remove_orphans = true;  // remove vertices that belong to no facet
};

struct Params {
  CoconeParams cocone;
  bool postprocess = true;
  PostParams post;
};

// Throws common::UsageError naming the option (--cocone-angle, ...) of the first parameter
// out of its range: cocone_angle (0, 90) deg, flat_ratio > 0, flat_angle (0, 90] deg,
// sharp_angle (0, 180] deg, min_height, max_area, max_aspect >= 0, max_aspect 0 or >= 1.
void validate(const Params& params);

struct ReconstructStats {
  std::size_t input_points = 0;
  std::size_t duplicates = 0;           // input rows merged into an earlier identical point
  std::size_t cells = 0;                // finite Delaunay tetrahedra
  std::size_t flat = 0;                 // samples marked flat (interior) by Dey–Giesen
  std::size_t flat_seeds = 0;           // flat before propagation
  std::size_t candidates = 0;           // cocone candidate triangles
  std::size_t pruned = 0;               // candidates deleted at sharp edges
  std::size_t umbrellas = 0;            // samples with an umbrella after pruning
  std::size_t faces = 0;                // output triangles
  std::size_t components = 0;           // edge-connected components of the output
  std::size_t boundary_edges = 0;       // edges with one output triangle
  std::size_t nonmanifold_dropped = 0;  // triangles dropped: edge with > 2, orientation conflict
  std::size_t flipped_components = 0;   // components reoriented to agree with the reference normals
};

struct Surface {
  std::vector<Face> faces;  // indices into the input points, consistently oriented per component
  ReconstructStats stats;
};

// Cocone surface of `points` (any order, duplicates allowed). `normals` is empty or one
// reference direction per point (fitvox normals): each connected component is oriented so
// that its faces are counter-clockwise seen from the side those normals point to; without
// them, closed components face outward (positive signed volume).
// Throws common::Error on fewer than 4 distinct points, non-finite coordinates, or coplanar
// input (no 3D Delaunay triangulation).
Surface reconstruct(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                    const CoconeParams& params);

struct PostStats {
  std::size_t low_vertices = 0;     // rule 1: z < min_height
  std::size_t partial_facets = 0;   // rule 2: facets left with < 3 vertices
  std::size_t large_facets = 0;     // rule 3: area >= max_area
  std::size_t sliver_facets = 0;    // rule 4: aspect > max_aspect
  std::size_t orphan_vertices = 0;  // rule 5: in no remaining facet
};

struct PostResult {
  std::vector<std::size_t> kept;  // surviving input rows, ascending
  std::vector<Face> faces;        // indices into `kept`
  PostStats stats;
};

// Thesis §4.5 post-processing, in the thesis order. `faces` index into `points`.
PostResult postprocess(const std::vector<Eigen::Vector3d>& points, const std::vector<Face>& faces,
                       const PostParams& params);

struct Inputs {
  const formats::PointCloud* samples = nullptr;  // the samples (borrowed)
};

using Outputs = formats::Mesh;

// Samples (x y z, optional normal_x/y/z, any other fields) -> mesh. Vertices are the rows
// that survive (every field kept, input order). Throws common::Error when the mesh has no
// face left.
Outputs run(const Params& params, const Inputs& inputs);

}  // namespace canopy::cocone
