// areas: where the target's surface area goes through the pipeline (issue 19). For one trial:
// the target's visible surface (from the labelled noise-free scan), the area its fitvox
// samples stand for, the target area of the cocone mesh, of the ncut segments, and of the
// X largest segments (the ones gmatch matches). All in m²; label 1 = target.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "canopy/documents/areas.h"
#include "canopy/documents/segment_graph.h"
#include "canopy/formats/ply.h"
#include "canopy/formats/point_cloud.h"

namespace canopy::areas {

// Visible surface area of a scan's points (one orthographic view per view id, pixel spacing
// `spacing`). Each point stands for its pixel's footprint on the surface, spacing² / |n·d|
// (d = its direction to the sensor, n = the surface normal: the smallest PCA axis of the
// points in the 3×3×3 cell neighbourhood on a cubic lattice of edge `cell`; |n·d| floored at
// `min_cos`). Views overlap, so per cell the area is the largest footprint sum of any one view
// (the union of the views' coverage is at least that; every view of a cell it sees whole
// gives the same sum). Exact for planes seen whole; see docs/decisions/noise.md.
struct ScanPoint {
  Eigen::Vector3d p, toward;  // position (m), unit direction to the sensor
  int view = 0;
};
double visible_area(const std::vector<ScanPoint>& points, double spacing, double cell, double min_cos = 0.05);

// Area the samples stand for: each sample its voxel's share h² / |n|₁ of a smooth surface
// (n = the sample's fitted normal): a plane of area A with unit normal n crosses on average
// A |n|₁ / h² voxels of edge h.
double samples_area(const std::vector<Eigen::Vector3d>& normals, double voxel);

// Target area of a mesh (vertices with x y z): each triangle's area times the share of its
// vertices labelled target (no label field: 0).
double mesh_area(const formats::Mesh& mesh, std::uint32_t label);

// Target area of segments: Σ area · label_purity over segments labelled `label`; `largest` > 0
// restricts the sum to the `largest` segments by area (all labels compete, ties by id: gmatch's
// order), 0 = every segment.
double segments_area(const documents::SegmentGraph& graph, std::uint32_t label, int largest);

using Areas = documents::Areas;  // areas.json (documents/areas.h)

inline constexpr int kMaxSegments = documents::kAreasMaxSegments;  // bound of --max-segments

struct Params {
  double spacing = 0.03;  // the scan's pixel spacing (m), [1 mm, 10 m]
  double cell = 0.045;    // lattice cell of the visible-area estimate (m), [spacing, 4 spacing]
  double voxel = 0.128;   // fitvox's voxel edge (m), [1 mm, 100 m]
  int max_segments = 15;  // gmatch's X, [1, kMaxSegments]
};

// Throws common::UsageError naming the option of the first parameter out of its range. The
// cell is bounded by the spacing: smaller, a neighbourhood misses the views that see it and
// their footprints are counted again (--cell 1e-6 gave 101.84 m² for 16.35).
void validate(const Params& params);

// One trial's artifacts, each with its file name for errors.
struct Inputs {
  formats::PointCloud scan;  // labelled noise-free scan: x y z sensor_x/y/z view_idx label
  std::string scan_name;
  formats::PointCloud samples;  // fitvox samples: normal_x/y/z label
  std::string samples_name;
  formats::Mesh mesh;  // cocone mesh: x y z label
  std::string mesh_name;
  documents::SegmentGraph segments;
  std::string segments_name;
};

using Outputs = Areas;

// Every area of the trial (DataError naming the file when a needed field is missing, a
// segment's area is negative or its label_purity outside [0, 1], or a sum is beyond 1e308).
Outputs run(const Params& params, const Inputs& inputs);

}  // namespace canopy::areas
