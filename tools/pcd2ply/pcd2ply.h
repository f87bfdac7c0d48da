// pcd2ply: a point cloud (PCD, LAS or PLY point set) as a PLY point set, every field kept as a
// vertex property, so scans and samples open in MeshLab and CloudCompare (MeshLab does not
// read PCD). The stage: the cloud becomes the vertices of a face-less mesh, its comments kept,
// the provenance lines appended.
#pragma once

#include "canopy/formats/ply.h"
#include "canopy/formats/point_cloud.h"
#include "canopy/formats/provenance.h"

namespace canopy::pcd2ply {

struct Params {
  bool ascii = false;  // write ascii PLY instead of binary little endian (used by the writer)
};

// Nothing to refuse: every Params is valid (kept for the one stage shape).
inline void validate(const Params&) {}

struct Inputs {
  formats::PointCloud cloud;
  formats::Provenance provenance;  // who writes the PLY from what (its comment lines)
};

using Outputs = formats::Mesh;

// The PLY point set of `cloud`: every field a vertex property, no faces; the cloud's comments
// then formats::provenance_comments(provenance). A cloud without x, y, z is refused
// (DataError naming provenance.inputs[0]): canopy could not read that PLY back.
Outputs run(const Params& params, const Inputs& inputs);

}  // namespace canopy::pcd2ply
