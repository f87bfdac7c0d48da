// Triangle meshes from other tools' files (rangetrace --model my.obj|.stl|.ply): Wavefront OBJ
// (v and f lines; polygons fanned into triangles; 1-based and negative indices; v/vt/vn words),
// STL (binary when its size matches its triangle count, else ASCII 'solid ...'; one vertex per
// facet corner, unwelded) and PLY (formats/ply.h). Coordinates are the file's own: no unit or
// axis conversion. Errors are DataErrors naming the file (and the line for OBJ).
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace canopy::formats {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> faces;  // indices into vertices
};

TriangleMesh parse_obj(const std::string& bytes, const std::string& name);
TriangleMesh parse_stl(const std::string& bytes, const std::string& name);
// By extension: "ply", "obj" or "stl" (lower case); any other is an Error.
TriangleMesh parse_triangle_mesh(const std::string& bytes, const std::string& name, const std::string& ext);

}  // namespace canopy::formats
