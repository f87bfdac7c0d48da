// Vehicle models: built-in POV-Ray includes, user includes, and mesh files (PLY/OBJ/STL)
// converted to a POV-Ray mesh2; the frame conversion.
#include <limits.h>
#include <stdlib.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/mesh_import.h"
#include "canopy/sim/families.h"
#include "canopy/sim/model.h"
#include "canopy/sim/sandbox.h"

namespace canopy::sim {

using common::DataError;

const char* const kBuiltinModels[5] = {"earthmover", "obj1", "sedan", "semi", "tank"};

Eigen::Vector3d pov_frame(const Eigen::Vector3d& v) { return {v.x(), v.z(), v.y()}; }

namespace {

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

std::string mesh2_declare(const std::string& name, const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<std::array<int, 3>>& faces, bool compact) {
  std::vector<std::array<int, 3>> kept;
  for (const auto& f : faces) {
    const Eigen::Vector3d a = vertices[f[0]], b = vertices[f[1]], c = vertices[f[2]];
    if ((b - a).cross(c - a).norm() > 1e-12) kept.push_back(f);  // POV-Ray drops degenerate ones
  }
  const char* indent = compact ? " " : "  ";
  const char* vertex = compact ? ",<%.7g,%.7g,%.7g>" : ",\n    <%.9g, %.9g, %.9g>";
  const char* face = compact ? ",<%d,%d,%d>" : ",\n    <%d, %d, %d>";
  const char* close = compact ? " }\n" : "\n  }\n";
  std::string out =
      "#declare " + name + " = mesh2 {\n" + indent + "vertex_vectors { " + std::to_string(vertices.size());
  out.reserve(out.size() + 40 * vertices.size() + 24 * kept.size());
  char buf[128];
  for (const auto& v : vertices) {
    const Eigen::Vector3d p = pov_frame(v);
    std::snprintf(buf, sizeof buf, vertex, p.x(), p.y(), p.z());
    out += buf;
  }
  out += std::string(close) + indent + "face_indices { " + std::to_string(kept.size());
  for (const auto& f : kept) {
    std::snprintf(buf, sizeof buf, face, f[0], f[1], f[2]);
    out += buf;
  }
  out += std::string(close) + "}\n";
  return out;
}

std::string mesh_to_pov(const std::vector<Eigen::Vector3d>& vertices,
                        const std::vector<std::array<int, 3>>& faces) {
  return mesh2_declare("Vehicle", vertices, faces, false);
}

std::string mesh_file_to_pov(const std::string& bytes, const std::string& name, const std::string& ext,
                             const MeshImport& import) {
  formats::TriangleMesh mesh = formats::parse_triangle_mesh(bytes, name, ext);
  if (mesh.faces.empty()) throw DataError(name, "mesh has no faces");
  for (auto& v : mesh.vertices) {
    if (!v.allFinite()) throw DataError(name, "non-finite vertex coordinate");
    v *= import.scale;
    if (!import.z_up) v = Eigen::Vector3d(v.x(), -v.z(), v.y());  // y-up right-handed -> z-up
  }
  return mesh_to_pov(mesh.vertices, mesh.faces);
}

Model load_model(const std::string& spec, const MeshImport& import) {
  Model model;
  for (const char* builtin : kBuiltinModels) {
    if (spec == builtin) {
      model.name = builtin;
      model.include_dir = common::share_dir() + "/models";
      model.include_file = model.name + ".inc";
      return model;
    }
  }
  if (is_family_spec(spec)) {
    FamilyInstance f = family_from_spec(spec);
    model.name = f.name;
    model.inline_code = std::move(f.pov);
    model.vehicle_class = f.vehicle_class;
    return model;
  }
  const std::string ext = lower_extension(spec);
  const auto slash = spec.find_last_of('/');
  const std::string base = slash == std::string::npos ? spec : spec.substr(slash + 1);
  model.name = base.substr(0, base.find_last_of('.'));
  if (ext == "inc" || ext == "pov") {
    common::read_file(spec);  // fails early, naming the file, when unreadable
    std::string dir = slash == std::string::npos ? "." : spec.substr(0, slash);
    if (dir.empty()) dir = "/";
    char real[PATH_MAX];
    if (::realpath(dir.c_str(), real) == nullptr) throw DataError(spec, "cannot resolve its directory");
    model.include_dir = real;
    model.include_file = base;
    model.user_files = check_user_include(model.include_dir, base, sandbox_mode() == SandboxMode::kOff);
    return model;
  }
  if (ext != "ply" && ext != "obj" && ext != "stl") {
    std::string names;
    for (const char* b : kBuiltinModels) names += std::string(names.empty() ? "" : ", ") + b;
    throw common::UsageError("--model '" + spec + "': not a built-in model (" + names +
                             "), a family:<class>:<instance> nor a .inc/.pov/.ply/.obj/.stl file");
  }
  model.inline_code = mesh_file_to_pov(common::read_file(spec), spec, ext, import);
  return model;
}

}  // namespace canopy::sim
