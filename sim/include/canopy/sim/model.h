// The simulator's models (sim/, docs/decisions/structure.md "sim/"): the vehicle a scan or a
// tile places, as POV-Ray code, and the one conversion between the world frame and POV-Ray's.
//
// Frames: the world frame is right-handed, z up, ground z = 0, metres. POV-Ray's frame is
// left-handed, y up. pov_frame() is the only place that converts between the two.
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace canopy::sim {

// The one conversion between the world frame (right-handed, z up) and POV-Ray's frame
// (left-handed, y up): it swaps y and z, which also flips handedness. It is its own inverse.
Eigen::Vector3d pov_frame(const Eigen::Vector3d& v);

// POV-Ray code declaring `Vehicle` (one object, ground at y = 0, metres, no textures: an
// inner texture would override the range coding).
struct Model {
  std::string name;
  std::string include_dir;    // passed to POV-Ray with +L ("" = the include is written inline)
  std::string include_file;   // file name inside include_dir
  std::string inline_code;    // used when include_dir is empty (converted meshes)
  std::string vehicle_class;  // procedural family instances (families.h): their class
  // A user include (.inc/.pov): include_dir is its real directory, and these are the files of
  // that directory POV-Ray may read (the include and what it names), approved by the include
  // check (sandbox.h); POV-Ray then runs confined. Empty for built-ins, families and meshes.
  std::vector<std::string> user_files;
};

struct MeshImport {
  double scale = 1.0;  // file units -> metres (mm 0.001, cm 0.01, m 1)
  bool z_up = true;    // file frame: z up (right-handed) or y up (right-handed, x right)
};

// Built-in name (share/models/<name>.inc), a procedural family instance
// (family:<class>:<instance>, families.h), a POV-Ray include (.inc/.pov) declaring Vehicle, or
// a mesh file (.ply/.obj/.stl) converted to a POV-Ray mesh2. An include is checked first
// (check_user_include, sandbox.h): a DataError names its file and line when it would write a
// file or read one outside its directory.
Model load_model(const std::string& spec, const MeshImport& import);
// POV-Ray code `#declare <name> = mesh2 {...}` of triangles (world-frame vertices in metres;
// degenerate triangles dropped, as POV-Ray would drop them). compact: each block on one line,
// 7 significant digits (the tiles' many meshes); else one vertex or face a line, 9 digits.
std::string mesh2_declare(const std::string& name, const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<std::array<int, 3>>& faces, bool compact);
// Mesh triangles (world-frame vertices in metres) -> POV-Ray code declaring Vehicle.
std::string mesh_to_pov(const std::vector<Eigen::Vector3d>& vertices,
                        const std::vector<std::array<int, 3>>& faces);
// The bytes of a mesh file (ext: "ply", "obj" or "stl", lower case) -> POV-Ray code declaring
// Vehicle, as load_model does for a mesh path; errors are DataErrors naming `name`.
std::string mesh_file_to_pov(const std::string& bytes, const std::string& name, const std::string& ext,
                             const MeshImport& import);
extern const char* const kBuiltinModels[5];

}  // namespace canopy::sim
