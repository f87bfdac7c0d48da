// ncut: segmentation of a reconstructed surface mesh into low-order surface patches by
// recursive two-way normalized cuts over the thesis affinity (ch. 5.3), and the segment
// attributes of ch. 5.5 (area, PCA radii, thickness, elongation, centroid, normal, label,
// adjacency). The stage is a plain function: no I/O.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/documents/segment_graph.h"
#include "canopy/formats/ply.h"
#include "ncut/affinity.h"
#include "ncut/cut.h"

namespace canopy::ncut {

// How the segment's PCA and centroid weight the surface.
enum class PcaWeighting {
  kSurface,   // exact moments of the surface each vertex owns (a third of each triangle,
              // its barycentric cell): independent of the sampling density
  kVertices,  // every vertex counts once (the thesis's "all of the points in the segment")
};

struct Params {
  ThesisAffinityParams affinity;  // sigma_n 10 deg, E 2, r 512 mm, exponent
  SparsifyParams sparsify;        // 175 mm, 25 %, 0.1, mesh edges kept, seed (r: affinity)
  CutParams cut;                  // Ncut < 0.1, solver settings
  PcaWeighting pca = PcaWeighting::kSurface;
};

// Throws common::UsageError naming the option (--sigma-n, ...) of the first parameter out of
// its range; lengths beyond [1 mm, 100 m] are not a mesh of a vehicle.
void validate(const Params& params);

struct Inputs {
  std::vector<Eigen::Vector3d> points;   // m
  std::vector<Eigen::Vector3d> normals;  // unit; empty = compute from the faces
  std::vector<std::uint32_t> labels;     // ground truth per vertex; empty = all unknown (0)
  std::vector<std::array<int, 3>> faces;
};

struct Stats {
  bool normals_computed = false;
  int vertices_without_normal = 0;  // no usable input normal and no incident face
  GraphStats graph;
  CutStats cut;
  double seconds_graph = 0, seconds_cut = 0, seconds_attributes = 0;
};

struct Result {
  documents::SegmentGraph graph;  // segments + adjacency (provenance and mesh left empty)
  std::vector<int> segment;       // segment id per vertex
  Stats stats;
};

using Outputs = Result;

// Validates a mesh read by formats::read_ply (x y z required; normal_x/y/z and label
// optional; finite coordinates; face indices in range, no repeated index) and converts it.
// `name` is the file name used in DataError messages.
Inputs input_from_mesh(const formats::Mesh& mesh, const std::string& name);

// Area-weighted vertex normals (sum of incident face normals, each weighted by its area);
// zero for vertices without faces.
std::vector<Eigen::Vector3d> vertex_normals(const std::vector<Eigen::Vector3d>& points,
                                            const std::vector<std::array<int, 3>>& faces);

// Unique undirected mesh edges (a < b), ascending.
std::vector<std::array<int, 2>> mesh_edges(const std::vector<std::array<int, 3>>& faces);

Outputs run(const Params& params, const Inputs& inputs);

// Every segment has an area > 0 (what read_segment_graph and gmatch require); else a DataError
// naming `name` (the mesh) and the segment. A mesh whose faces all have zero area is refused
// earlier, by input_from_mesh.
void check_segments(const Result& result, const std::string& name);

// Attributes of the segments given a segment id per vertex (ids 0..k-1, each used).
std::vector<documents::Segment> segment_attributes(const Inputs& in,
                                                   const std::vector<Eigen::Vector3d>& normals,
                                                   const std::vector<int>& segment, int count,
                                                   PcaWeighting pca);
// Segment pairs sharing mesh edges, ascending (a, b), a < b.
std::vector<documents::SegmentEdge> segment_adjacency(const std::vector<std::array<int, 3>>& faces,
                                                      const std::vector<int>& segment);

// Fixed colour of a segment id (well-separated hues by the golden ratio).
std::array<std::uint8_t, 3> segment_colour(int segment_id);
// The input mesh with `segment` (int) and red/green/blue (uchar) vertex fields added.
formats::Mesh colored_mesh(const formats::Mesh& mesh, const std::vector<int>& segment);

}  // namespace canopy::ncut
