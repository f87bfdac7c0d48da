// PLY triangle meshes and point sets (Stanford format 1.0). See formats/README.md.
// Reads ascii, binary_little_endian and binary_big_endian; any scalar vertex properties;
// faces as "vertex_indices" or "vertex_index" lists (polygons are fan-triangulated).
// Writes binary_little_endian (or ascii). Vertex property names are the PointCloud field
// names, except normals: PointCloud normal_x/normal_y/normal_z <-> PLY nx/ny/nz
// (MeshLab's names), and colours red/green/blue are uchar.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"

namespace canopy::formats {

struct Mesh {
  PointCloud vertices;                           // at least x, y, z
  std::vector<std::array<std::int32_t, 3>> faces;  // counter-clockwise seen from outside
};

Mesh read_ply(const std::string& path);
Mesh parse_ply(const std::string& bytes, const std::string& name);

// Writes atomically. Face indices must be < vertex count (checked).
void write_ply(const Mesh& mesh, const std::string& path, bool ascii = false);
std::string serialize_ply(const Mesh& mesh, bool ascii = false);

}  // namespace canopy::formats
