// Orientation of the walked surface: each facet toward its front cell, edges kept at <= 2
// triangles, breadth-first orientation propagation, then per-component orientation from the
// reference normals (or the signed volume); finish() fills the Surface and its statistics.

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "canopy/common/log.h"

#include "cocone/reconstructor.h"

namespace canopy::cocone::detail {

namespace {

// Undirected edges of a triangle list: (a, b, face) with a < b, sorted; group[g]..group[g+1]
// are the rows of edge g.
struct EdgeTable {
  std::vector<std::array<int, 3>> es;
  std::vector<std::size_t> group;
};

EdgeTable edge_table(const std::vector<Face>& faces) {
  EdgeTable e;
  e.es.reserve(3 * faces.size());
  for (std::size_t t = 0; t < faces.size(); ++t) {
    for (int s = 0; s < 3; ++s) {
      int a = faces[t][s], b = faces[t][(s + 1) % 3];
      if (a > b) std::swap(a, b);
      e.es.push_back({a, b, static_cast<int>(t)});
    }
  }
  std::sort(e.es.begin(), e.es.end());
  e.group.assign(1, 0);
  for (std::size_t k = 1; k <= e.es.size(); ++k) {
    if (k == e.es.size() || e.es[k][0] != e.es[k - 1][0] || e.es[k][1] != e.es[k - 1][1])
      e.group.push_back(k);
  }
  return e;
}

// Keeps every edge at <= 2 triangles (the first accepted win); returns how many were dropped.
std::size_t drop_nonmanifold(const EdgeTable& e, std::vector<std::uint8_t>& drop) {
  std::size_t nonmanifold = 0;
  for (std::size_t g = 0; g + 1 < e.group.size(); ++g) {
    for (std::size_t q = e.group[g]; q < e.group[g + 1]; ++q) {
      if (q < e.group[g] + 2) continue;
      const int t = e.es[q][2];
      if (!drop[t]) ++nonmanifold;
      drop[t] = 1;
    }
  }
  return nonmanifold;
}

// Neighbour of each live triangle across its edge (s, s+1) when that edge has exactly two
// live triangles; -1 otherwise.
std::vector<std::array<int, 3>> edge_neighbours(const std::vector<Face>& faces, const EdgeTable& e,
                                                const std::vector<std::uint8_t>& drop) {
  std::vector<std::array<int, 3>> adj(faces.size(), {-1, -1, -1});
  for (std::size_t g = 0; g + 1 < e.group.size(); ++g) {
    int live[2], m = 0;
    for (std::size_t q = e.group[g]; q < e.group[g + 1]; ++q)
      if (!drop[e.es[q][2]] && m < 2) live[m++] = e.es[q][2];
    if (m != 2) continue;
    const int t1 = live[0], t2 = live[1];
    const int lo = e.es[e.group[g]][0], hi = e.es[e.group[g]][1];
    for (int s = 0; s < 3; ++s) {
      const int a = faces[t1][s], b = faces[t1][(s + 1) % 3];
      if (std::min(a, b) == lo && std::max(a, b) == hi) adj[t1][s] = t2;
      const int c = faces[t2][s], d = faces[t2][(s + 1) % 3];
      if (std::min(c, d) == lo && std::max(c, d) == hi) adj[t2][s] = t1;
    }
  }
  return adj;
}

// Consistent orientation by breadth-first propagation across 2-triangle edges. The walk
// orients almost everything already; where it met a triangle from its back side (noisy,
// non-manifold candidate sets) the triangle is flipped here, and a triangle that cannot be
// made consistent (non-orientable pocket) is dropped. Fills comp (component per triangle);
// returns the number of components.
int propagate_orientation(std::vector<Face>& faces, std::vector<std::array<int, 3>>& adj,
                          std::vector<std::uint8_t>& drop, std::vector<int>& comp, std::size_t* flipped_faces,
                          std::size_t* conflicts) {
  const std::size_t nf = faces.size();
  auto has_directed = [&](int t, int a, int b) {
    for (int s = 0; s < 3; ++s)
      if (faces[t][s] == a && faces[t][(s + 1) % 3] == b) return true;
    return false;
  };
  comp.assign(nf, -1);
  int ncomp = 0;
  std::vector<int> queue;
  for (std::size_t t0 = 0; t0 < nf; ++t0) {
    if (drop[t0] || comp[t0] >= 0) continue;
    queue.assign(1, static_cast<int>(t0));
    comp[t0] = ncomp;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int t = queue[head];
      if (drop[t]) continue;
      for (int s = 0; s < 3; ++s) {
        const int h = adj[t][s];
        if (h < 0 || drop[h]) continue;
        const int a = faces[t][s], b = faces[t][(s + 1) % 3];
        const bool consistent = has_directed(h, b, a);
        if (comp[h] < 0) {
          if (!consistent) {
            std::swap(faces[h][1], faces[h][2]);
            std::swap(adj[h][0], adj[h][2]);  // edge slots follow the vertex order
            ++*flipped_faces;
          }
          comp[h] = ncomp;
          queue.push_back(h);
        } else if (!consistent) {
          drop[h] = 1;  // h was oriented earlier from another side: non-orientable here
          ++*conflicts;
        }
      }
    }
    ++ncomp;
  }
  return ncomp;
}

// Edges with exactly one live triangle.
std::size_t boundary_edges(const EdgeTable& e, const std::vector<std::uint8_t>& drop) {
  std::size_t boundary = 0;
  for (std::size_t g = 0; g + 1 < e.group.size(); ++g) {
    int live = 0;
    for (std::size_t q = e.group[g]; q < e.group[g + 1]; ++q) live += !drop[e.es[q][2]];
    boundary += live == 1;
  }
  return boundary;
}

}  // namespace

// Each accepted facet, oriented so that its normal points into its front cell.
std::vector<Face> Reconstructor::oriented_facets() const {
  std::vector<Face> faces;
  faces.reserve(order_.size());
  for (int f : order_) {
    const int cell = front_[f];
    int j = 3;
    for (int i = 0; i < 3; ++i)
      if (fidx_[4 * cell + i] == f) j = i;
    Face tri{t_.cv[4 * cell + (j + 1) % 4], t_.cv[4 * cell + (j + 2) % 4], t_.cv[4 * cell + (j + 3) % 4]};
    int o = t_.cv[4 * cell + j];
    CGAL::Orientation want = CGAL::POSITIVE;
    if (o < 0) {
      const int nb = t_.nbr[4 * cell + j];
      o = t_.cv[4 * nb + t_.nbri[4 * cell + j]];
      want = CGAL::NEGATIVE;
    }
    if (CGAL::orientation(cp_[tri[0]], cp_[tri[1]], cp_[tri[2]], cp_[o]) != want) std::swap(tri[1], tri[2]);
    faces.push_back(tri);
  }
  return faces;
}

// Per-component orientation score: agreement with the reference normals, or (without them)
// the signed volume about the component's centroid; < 0 = the component faces the wrong way.
std::vector<double> Reconstructor::component_scores(const std::vector<Face>& faces,
                                                    const std::vector<std::uint8_t>& drop,
                                                    const std::vector<int>& comp, int ncomp) const {
  const std::size_t nf = faces.size();
  std::vector<double> score(ncomp, 0.0);
  std::vector<V3> centroid(ncomp, V3::Zero());
  std::vector<double> count(ncomp, 0.0);
  const bool have_normals = !normals_.empty();
  if (!have_normals) {
    for (std::size_t t = 0; t < nf; ++t) {
      if (drop[t]) continue;
      for (int v : faces[t]) centroid[comp[t]] += p_[v];
      count[comp[t]] += 3;
    }
    for (int c = 0; c < ncomp; ++c)
      if (count[c] > 0) centroid[c] /= count[c];
  }
  for (std::size_t t = 0; t < nf; ++t) {
    if (drop[t]) continue;
    const V3& a = p_[faces[t][0]];
    const V3& b = p_[faces[t][1]];
    const V3& c = p_[faces[t][2]];
    if (have_normals) {
      const V3 nrm = (b - a).cross(c - a);
      for (int v : faces[t]) score[comp[t]] += nrm.dot(normals_[row_of_[v]]);
    } else {
      const V3& o = centroid[comp[t]];
      score[comp[t]] += (a - o).dot((b - o).cross(c - o));
    }
  }
  return score;
}

Surface Reconstructor::finish() {
  common::log::Phase phase("orient");
  std::vector<Face> faces = oriented_facets();
  const std::size_t nf = faces.size();
  std::vector<std::uint8_t> drop(nf, 0);
  const EdgeTable edges = edge_table(faces);
  const std::size_t nonmanifold = drop_nonmanifold(edges, drop);
  std::vector<std::array<int, 3>> adj = edge_neighbours(faces, edges, drop);
  std::vector<int> comp;
  std::size_t flipped_faces = 0, conflicts = 0;
  const int ncomp = propagate_orientation(faces, adj, drop, comp, &flipped_faces, &conflicts);
  const std::vector<double> score = component_scores(faces, drop, comp, ncomp);
  Surface out;
  out.stats = st_;
  out.stats.components = static_cast<std::size_t>(ncomp);
  for (int c = 0; c < ncomp; ++c) out.stats.flipped_components += score[c] < 0;
  for (std::size_t t = 0; t < nf; ++t) {
    if (drop[t]) continue;
    Face f{row_of_[faces[t][0]], row_of_[faces[t][1]], row_of_[faces[t][2]]};
    if (score[comp[t]] < 0) std::swap(f[1], f[2]);
    out.faces.push_back(f);
  }
  out.stats.nonmanifold_dropped = nonmanifold + conflicts;
  out.stats.boundary_edges = boundary_edges(edges, drop);
  out.stats.faces = out.faces.size();
  phase.done(std::to_string(out.faces.size()) + " triangles in " + std::to_string(ncomp) + " components, " +
             std::to_string(flipped_faces) + " flipped to agree with their " + "neighbours, " +
             std::to_string(nonmanifold) + " dropped at edges with > 2 triangles, " +
             std::to_string(conflicts) + " dropped as orientation conflicts");
  return out;
}

}  // namespace canopy::cocone::detail
