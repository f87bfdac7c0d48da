#include "canopy/formats/mesh_import.h"

#include <cstdint>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "canopy/common/error.h"
#include "canopy/formats/cloud_eigen.h"
#include "canopy/formats/ply.h"

namespace canopy::formats {

using common::DataError;

namespace {

void add_polygon(const std::vector<int>& poly, TriangleMesh* mesh) {
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) mesh->faces.push_back({poly[0], poly[k], poly[k + 1]});
}

// The vertex index of an OBJ face word ("7", "7/1", "7//3", "-1"), 0-based; errors name the line.
int obj_index(const std::string& w, int vertices, const std::string& path, int line_no) {
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
  idx = idx < 0 ? vertices + idx : idx - 1;
  if (idx < 0 || idx >= vertices)
    throw DataError(path, "line " + std::to_string(line_no) + ": face index out of range");
  return idx;
}

// Binary STL when the size matches the triangle count in its header; false otherwise.
bool parse_binary_stl(const std::string& bytes, TriangleMesh* mesh) {
  if (bytes.size() < 84) return false;
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  if (bytes.size() != 84 + 50ull * n) return false;
  for (std::uint32_t t = 0; t < n; ++t) {
    const char* rec = bytes.data() + 84 + 50ull * t + 12;
    std::array<int, 3> f{};
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, rec + 12 * k, 12);
      mesh->vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
      f[k] = static_cast<int>(mesh->vertices.size() - 1);
    }
    mesh->faces.push_back(f);
  }
  return true;
}

}  // namespace

TriangleMesh parse_obj(const std::string& bytes, const std::string& path) {
  TriangleMesh mesh;
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
      if (!(ls >> x >> y >> z))
        throw DataError(path, "line " + std::to_string(line_no) + ": malformed vertex");
      mesh.vertices.emplace_back(x, y, z);
    } else if (tag == "f") {
      std::vector<int> poly;
      for (std::string w; ls >> w;) {
        poly.push_back(obj_index(w, static_cast<int>(mesh.vertices.size()), path, line_no));
      }
      if (poly.size() < 3)
        throw DataError(path, "line " + std::to_string(line_no) + ": face with fewer than 3 vertices");
      add_polygon(poly, &mesh);
    }
  }
  return mesh;
}

TriangleMesh parse_stl(const std::string& bytes, const std::string& path) {
  TriangleMesh mesh;
  if (parse_binary_stl(bytes, &mesh)) return mesh;
  if (bytes.compare(0, 5, "solid") != 0) {
    if (bytes.size() < 84) {
      throw DataError(path, "neither ASCII STL ('solid ...') nor binary STL (" + std::to_string(bytes.size()) +
                                " bytes, shorter than a binary STL's 84-byte header)");
    }
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    throw DataError(path, "neither ASCII STL ('solid ...') nor binary STL of consistent size: the header's " +
                              std::to_string(n) + " triangles need " + std::to_string(84 + 50ull * n) +
                              " bytes, the file holds " + std::to_string(bytes.size()) +
                              (bytes.size() < 84 + 50ull * n ? " (truncated?)" : ""));
  }
  std::istringstream in(bytes);
  std::vector<int> poly;
  bool in_facet = false;
  for (std::string w; in >> w;) {
    if (w == "facet") in_facet = true;
    if (w == "endfacet") in_facet = false;
    if (w == "vertex") {
      double x, y, z;
      if (!(in >> x >> y >> z)) throw DataError(path, "malformed 'vertex' line");
      mesh.vertices.emplace_back(x, y, z);
      poly.push_back(static_cast<int>(mesh.vertices.size() - 1));
    } else if (w == "endloop") {
      if (poly.size() < 3) throw DataError(path, "facet with fewer than 3 vertices");
      add_polygon(poly, &mesh);
      poly.clear();
    }
  }
  // Cut inside a facet (it read as the facets before it, or "mesh has no faces").
  if (in_facet || !poly.empty()) {
    throw DataError(path, "ASCII STL truncated: the file ends inside a facet (after " +
                              std::to_string(mesh.faces.size()) + " complete triangles)");
  }
  return mesh;
}

TriangleMesh parse_triangle_mesh(const std::string& bytes, const std::string& name, const std::string& ext) {
  if (bytes.empty() && (ext == "obj" || ext == "stl")) {
    throw DataError(name, std::string("empty file (not an ") + (ext == "obj" ? "OBJ" : "STL") + " mesh)");
  }
  if (ext == "obj") return parse_obj(bytes, name);
  if (ext == "stl") return parse_stl(bytes, name);
  if (ext != "ply") throw common::Error(name + ": not a mesh file extension: '" + ext + "'");
  const Mesh m = parse_ply(bytes, name);
  TriangleMesh mesh;
  mesh.vertices = to_vectors(m.vertices);
  for (const auto& f : m.faces) mesh.faces.push_back({f[0], f[1], f[2]});
  return mesh;
}

}  // namespace canopy::formats
