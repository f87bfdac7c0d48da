// Vehicle models: built-in POV-Ray includes, user includes, and mesh files (PLY/OBJ/STL)
// converted to a POV-Ray mesh2.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/formats/ply.h"
#include "rangetrace/families.h"
#include "rangetrace/rangetrace.h"

namespace canopy::rangetrace {

using common::DataError;

const char* const kBuiltinModels[5] = {"earthmover", "obj1", "sedan", "semi", "tank"};

namespace {

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

struct RawMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> faces;
};

void add_polygon(const std::vector<int>& poly, RawMesh* mesh) {
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) mesh->faces.push_back({poly[0], poly[k], poly[k + 1]});
}

RawMesh read_obj(const std::string& bytes, const std::string& path) {
  RawMesh mesh;
  std::istringstream in(bytes);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag)) continue;
    if (tag == "v") {
      double x, y, z;
      if (!(ls >> x >> y >> z)) throw DataError(path, "line " + std::to_string(line_no) + ": malformed vertex");
      mesh.vertices.emplace_back(x, y, z);
    } else if (tag == "f") {
      std::vector<int> poly;
      for (std::string w; ls >> w;) {
        int idx = 0;
        try {
          // The vertex index is the whole word up to '/': "1.5" or "2x" are not indices.
          const std::string head = w.substr(0, w.find('/'));
          std::size_t used = 0;
          idx = std::stoi(head, &used);
          if (used != head.size()) throw std::invalid_argument(head);
        } catch (const std::logic_error&) {
          throw DataError(path, "line " + std::to_string(line_no) + ": malformed face index '" + w + "'");
        }
        const int n = static_cast<int>(mesh.vertices.size());
        idx = idx < 0 ? n + idx : idx - 1;
        if (idx < 0 || idx >= n) throw DataError(path, "line " + std::to_string(line_no) + ": face index out of range");
        poly.push_back(idx);
      }
      if (poly.size() < 3) throw DataError(path, "line " + std::to_string(line_no) + ": face with fewer than 3 vertices");
      add_polygon(poly, &mesh);
    }
  }
  return mesh;
}

RawMesh read_stl(const std::string& bytes, const std::string& path) {
  RawMesh mesh;
  auto push = [&](const Eigen::Vector3d& v) {
    mesh.vertices.push_back(v);
    return static_cast<int>(mesh.vertices.size() - 1);
  };
  if (bytes.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    if (bytes.size() == 84 + 50ull * n) {
      for (std::uint32_t t = 0; t < n; ++t) {
        const char* rec = bytes.data() + 84 + 50ull * t + 12;
        std::array<int, 3> f{};
        for (int k = 0; k < 3; ++k) {
          float xyz[3];
          std::memcpy(xyz, rec + 12 * k, 12);
          f[k] = push(Eigen::Vector3d(xyz[0], xyz[1], xyz[2]));
        }
        mesh.faces.push_back(f);
      }
      return mesh;
    }
  }
  if (bytes.compare(0, 5, "solid") != 0) {
    throw DataError(path, "neither ASCII STL ('solid ...') nor binary STL of consistent size");
  }
  std::istringstream in(bytes);
  std::vector<int> poly;
  for (std::string w; in >> w;) {
    if (w == "vertex") {
      double x, y, z;
      if (!(in >> x >> y >> z)) throw DataError(path, "malformed 'vertex' line");
      poly.push_back(push(Eigen::Vector3d(x, y, z)));
    } else if (w == "endloop") {
      if (poly.size() < 3) throw DataError(path, "facet with fewer than 3 vertices");
      add_polygon(poly, &mesh);
      poly.clear();
    }
  }
  return mesh;
}

RawMesh parse_mesh(const std::string& bytes, const std::string& name, const std::string& ext) {
  if (ext == "ply") {
    const formats::Mesh m = formats::parse_ply(bytes, name);
    RawMesh mesh;
    const auto& x = m.vertices.col("x");
    const auto& y = m.vertices.col("y");
    const auto& z = m.vertices.col("z");
    for (std::size_t i = 0; i < m.vertices.size(); ++i) mesh.vertices.emplace_back(x[i], y[i], z[i]);
    for (const auto& f : m.faces) mesh.faces.push_back({f[0], f[1], f[2]});
    return mesh;
  }
  return ext == "obj" ? read_obj(bytes, name) : read_stl(bytes, name);
}

}  // namespace

std::string mesh_to_pov(const std::vector<Eigen::Vector3d>& vertices,
                        const std::vector<std::array<int, 3>>& faces) {
  std::vector<std::array<int, 3>> kept;
  for (const auto& f : faces) {
    const Eigen::Vector3d a = vertices[f[0]], b = vertices[f[1]], c = vertices[f[2]];
    if ((b - a).cross(c - a).norm() > 1e-12) kept.push_back(f);  // POV-Ray drops degenerate ones
  }
  std::string out = "#declare Vehicle = mesh2 {\n  vertex_vectors { " +
                    std::to_string(vertices.size());
  char buf[128];
  for (const auto& v : vertices) {
    const Eigen::Vector3d p = pov_frame(v);
    std::snprintf(buf, sizeof buf, ",\n    <%.9g, %.9g, %.9g>", p.x(), p.y(), p.z());
    out += buf;
  }
  out += "\n  }\n  face_indices { " + std::to_string(kept.size());
  for (const auto& f : kept) {
    std::snprintf(buf, sizeof buf, ",\n    <%d, %d, %d>", f[0], f[1], f[2]);
    out += buf;
  }
  out += "\n  }\n}\n";
  return out;
}

std::string mesh_file_to_pov(const std::string& bytes, const std::string& name,
                             const std::string& ext, const MeshImport& import) {
  RawMesh mesh = parse_mesh(bytes, name, ext);
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
    model.include_dir = slash == std::string::npos ? "." : spec.substr(0, slash);
    if (model.include_dir.empty()) model.include_dir = "/";
    model.include_file = base;
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

}  // namespace canopy::rangetrace
