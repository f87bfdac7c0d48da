// Cocone on CGAL's 3D Delaunay triangulation (Epick, robust circumcentres).
//
// CGAL is used for three things only: the Delaunay triangulation, the circumcentres and the
// orientation predicate. Right after the triangulation is built, its cells are copied into
// flat arrays indexed by cell id; vertex ids follow the lexicographic order of the points, so
// the result does not depend on the order of the input rows: same samples, same output bytes.
//
// Steps (shared spec ALGORITHMS.md §A): poles -> cocone test per Delaunay facet (closed-form
// polar-cone test) -> Dey–Giesen flatness (co-polygon width vs negative-pole height, normal
// condition, propagation) -> bound-cocone candidates -> umbrellas -> pruning of sharp edges
// between flat samples with umbrellas (never across holes: the cascade guard) ->
// orientation-consistent walk -> per-component orientation.

#include <Eigen/Geometry>
#include <CGAL/Robust_weighted_circumcenter_filtered_traits_3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "cocone/cocone.h"
#include "cocone/reconstructor.h"

namespace canopy::cocone {
namespace detail {
namespace {

Flat build_flat(const Delaunay& dt, std::vector<Delaunay::Cell_handle>& handles) {
  // Cell ids follow CGAL's iteration order. That order is a deterministic function of the
  // insertion sequence (vertex ids are in lexicographic point order and CGAL's spatial sort
  // seeds its own generator on every call), so ids do not depend on the input row order.
  handles.clear();
  handles.reserve(dt.number_of_cells() + 64);
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) handles.push_back(c);
  Flat f;
  f.cells = static_cast<int>(handles.size());
  for (int c = 0; c < f.cells; ++c) handles[c]->info() = c;
  f.cv.resize(4 * handles.size());
  f.nbr.resize(4 * handles.size());
  f.nbri.resize(4 * handles.size());
  for (int c = 0; c < f.cells; ++c) {
    const auto h = handles[c];
    for (int k = 0; k < 4; ++k) {
      const auto v = h->vertex(k);
      f.cv[4 * c + k] = dt.is_infinite(v) ? kInfinite : v->info();
      const auto n = h->neighbor(k);
      f.nbr[4 * c + k] = n->info();
      f.nbri[4 * c + k] = static_cast<std::int8_t>(n->index(h));
    }
  }
  return f;
}

}  // namespace

void Reconstructor::deduplicate() {
  const std::size_t n = input_.size();
  st_.input_points = n;
  for (std::size_t r = 0; r < n; ++r) {
    if (!input_[r].allFinite()) {
      throw common::Error("sample " + std::to_string(r) + " has a non-finite coordinate");
    }
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto& pa = input_[a];
    const auto& pb = input_[b];
    if (pa.x() != pb.x()) return pa.x() < pb.x();
    if (pa.y() != pb.y()) return pa.y() < pb.y();
    if (pa.z() != pb.z()) return pa.z() < pb.z();
    return a < b;
  });
  // Vertex ids follow the lexicographic order of the coordinates, so that every later step
  // (and hence the output triangle set) does not depend on the order of the input rows.
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || input_[order[k]] != input_[order[k - 1]]) {
      row_of_.push_back(order[k]);
      p_.push_back(input_[order[k]]);
    }
  }
  st_.duplicates = n - p_.size();
  if (p_.size() < 4) {
    throw common::Error("need at least 4 distinct samples to build a surface, got " + std::to_string(p_.size()) +
                        (st_.duplicates ? " (" + std::to_string(st_.duplicates) + " duplicates)" : ""));
  }
}

void Reconstructor::triangulate() {
  common::log::Phase phase("delaunay");
  std::vector<std::pair<Point, int>> pts;
  pts.reserve(p_.size());
  cp_.reserve(p_.size());
  for (std::size_t v = 0; v < p_.size(); ++v) {
    cp_.emplace_back(p_[v].x(), p_[v].y(), p_[v].z());
    pts.emplace_back(cp_.back(), static_cast<int>(v));
  }
  Delaunay dt(pts.begin(), pts.end());
  if (dt.dimension() < 3) {
    throw common::Error(std::string("all ") + std::to_string(p_.size()) + " distinct samples are " +
                        (dt.dimension() == 2 ? "coplanar" : "collinear") +
                        ": the 3D Delaunay triangulation is degenerate, no surface to reconstruct");
  }
  if (dt.number_of_vertices() != p_.size()) {
    throw common::Error("internal: Delaunay merged distinct samples");
  }
  const double t_dt = phase.seconds();
  std::vector<Delaunay::Cell_handle> handles;
  t_ = build_flat(dt, handles);
  const double t_flat = phase.seconds();

  // Voronoi vertices: robust circumcentres (exact fallback when the double formula is unsafe).
  CGAL::Robust_circumcenter_filtered_traits_3<K> traits;
  const auto circumcenter = traits.construct_circumcenter_3_object();
  cc_.assign(t_.cells, V3::Zero());
  std::size_t finite = 0;
  for (int c = 0; c < t_.cells; ++c) {
    if (!t_.finite(c)) continue;
    ++finite;
    const auto& a = cp_[t_.cv[4 * c]];
    const auto& b = cp_[t_.cv[4 * c + 1]];
    const auto& d = cp_[t_.cv[4 * c + 2]];
    const auto& e = cp_[t_.cv[4 * c + 3]];
    V3 x = to_v3(circumcenter(a, b, d, e));
    if (!x.allFinite()) x = (to_v3(a) + to_v3(b) + to_v3(d) + to_v3(e)) / 4;
    cc_[c] = x;
  }
  st_.cells = finite;
  common::log::debug("delaunay " + std::to_string(t_dt) + " s, index " + std::to_string(t_flat - t_dt) +
                     " s, circumcentres " + std::to_string(phase.seconds() - t_flat) + " s");
  phase.done(std::to_string(p_.size()) + " samples, " + std::to_string(finite) + " tetrahedra" +
             (st_.duplicates ? ", " + std::to_string(st_.duplicates) + " duplicate rows merged" : ""));
}

Surface Reconstructor::run() {
  deduplicate();
  triangulate();
  {
    common::log::Phase phase("cocone");
    poles();
    cocone_tests();
    phase.done(std::to_string(facets_.size()) + " Delaunay triangles tested against the cocones");
  }
  flatness();
  candidates();
  build_complex();
  prune();
  walk();
  return finish();
}

}  // namespace detail

Surface reconstruct(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                    const CoconeParams& params) {
  if (!normals.empty() && normals.size() != points.size()) {
    throw common::Error("internal: " + std::to_string(normals.size()) + " normals for " +
                        std::to_string(points.size()) + " points");
  }
  if (points.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 8)) {
    throw common::Error("too many samples for one mesh: " + std::to_string(points.size()));
  }
  detail::Reconstructor r(points, normals, params);
  return r.run();
}

}  // namespace canopy::cocone
