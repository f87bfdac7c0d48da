// PLY triangle meshes and point sets (Stanford format 1.0). See formats/README.md.
// Reads ascii, binary_little_endian and binary_big_endian; any scalar vertex properties;
// faces as "vertex_indices" or "vertex_index" lists (polygons are fan-triangulated);
// "scalar_<name>" vertex properties (CloudCompare) become column <name>. Element counts and
// list lengths are checked against the data before anything is allocated.
// Writes binary_little_endian (or ascii). Vertex property names are the PointCloud field
// names, except normals: PointCloud normal_x/normal_y/normal_z <-> PLY nx/ny/nz
// (MeshLab's names), and colours red/green/blue (alpha) are uchar: when any red, green or blue
// value is above 255 (LAS colour is 16-bit) the three are written as value / 256, floored (the
// high byte), with a header comment saying so; alpha alike on its own; 8-bit colours as they are.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/formats/point_cloud.h"

namespace canopy::formats {

struct Mesh {
  PointCloud vertices;                             // at least x, y, z
  std::vector<std::array<std::int32_t, 3>> faces;  // counter-clockwise seen from outside
};

Mesh read_ply(const std::string& path);
Mesh parse_ply(const std::string& bytes, const std::string& name);

struct PlyWriteOptions {
  bool ascii = false;  // format ascii 1.0 instead of binary_little_endian 1.0
  // Name every vertex property other than x y z nx ny nz red green blue alpha "scalar_<name>",
  // so CloudCompare loads them as scalar fields (our reader strips the prefix again).
  bool scalar_prefix = false;
};

// Writes atomically. Face indices must be < vertex count (checked). uint32 (U4) columns are
// written as PLY int when every value fits (Open3D skips uint), otherwise as uint.
void write_ply(const Mesh& mesh, const std::string& path, bool ascii = false);
void write_ply(const Mesh& mesh, const std::string& path, const PlyWriteOptions& options);
std::string serialize_ply(const Mesh& mesh, bool ascii = false);
std::string serialize_ply(const Mesh& mesh, const PlyWriteOptions& options);

}  // namespace canopy::formats
