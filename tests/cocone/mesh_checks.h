// Topology checks on triangle meshes for the cocone tests.
#pragma once

#include <Eigen/Geometry>
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "cocone/cocone.h"

namespace cocone_test {

using canopy::cocone::Face;

struct Topology {
  std::size_t vertices = 0;  // referenced by a face
  std::size_t edges = 0;
  std::size_t faces = 0;
  std::size_t boundary_edges = 0;      // one incident face
  std::size_t nonmanifold_edges = 0;   // > 2 incident faces
  std::size_t inconsistent_edges = 0;  // a directed edge used twice (orientation flip)
  std::size_t boundary_loops = 0;      // connected components of the boundary edge graph
  long euler() const {
    return static_cast<long>(vertices) - static_cast<long>(edges) + static_cast<long>(faces);
  }
};

inline Topology topology(const std::vector<Face>& faces) {
  Topology t;
  t.faces = faces.size();
  std::map<std::pair<int, int>, int> undirected;
  std::map<std::pair<int, int>, int> directed;
  std::set<int> verts;
  for (const Face& f : faces) {
    for (int s = 0; s < 3; ++s) {
      const int a = f[s], b = f[(s + 1) % 3];
      verts.insert(a);
      ++undirected[{std::min(a, b), std::max(a, b)}];
      ++directed[{a, b}];
    }
  }
  t.vertices = verts.size();
  t.edges = undirected.size();
  std::map<int, int> parent;
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& [e, n] : undirected) {
    if (n == 1) {
      ++t.boundary_edges;
      for (int v : {e.first, e.second})
        if (!parent.count(v)) parent[v] = v;
      parent[find(e.first)] = find(e.second);
    }
    if (n > 2) ++t.nonmanifold_edges;
  }
  for (const auto& [e, n] : directed)
    if (n > 1) ++t.inconsistent_edges;
  for (const auto& [v, p] : parent)
    if (find(v) == v) ++t.boundary_loops;
  return t;
}

inline double signed_volume(const std::vector<Eigen::Vector3d>& p, const std::vector<Face>& faces) {
  double v = 0;
  for (const Face& f : faces) v += p[f[0]].dot(p[f[1]].cross(p[f[2]])) / 6.0;
  return v;
}

}  // namespace cocone_test
