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
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_weighted_circumcenter_filtered_traits_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>
#include <vector>

#include "canopy/common/error.h"
#include "canopy/common/log.h"
#include "cocone/cocone.h"

namespace canopy::cocone {
namespace {

using K = CGAL::Epick;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<int, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<int, K, CGAL::Delaunay_triangulation_cell_base_3<K>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb, CGAL::Sequential_tag>;
using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds>;
using Point = K::Point_3;
using V3 = Eigen::Vector3d;

constexpr int kInfinite = -1;

// The triangulation as flat arrays. Cell c has vertices cv[4c+k] (kInfinite for the infinite
// vertex), neighbours nbr[4c+k] (opposite vertex k) and nbri[4c+k] = index of c in that
// neighbour.
struct Flat {
  int cells = 0;
  std::vector<int> cv, nbr;
  std::vector<std::int8_t> nbri;
  bool finite(int c) const {
    return cv[4 * c] >= 0 && cv[4 * c + 1] >= 0 && cv[4 * c + 2] >= 0 && cv[4 * c + 3] >= 0;
  }
  int local(int c, int v) const {
    for (int k = 0; k < 4; ++k)
      if (cv[4 * c + k] == v) return k;
    return -1;
  }
};

// A finite Delaunay triangle, stored once: cell c, facet index i; v = its vertices in local
// order (i+1, i+2, i+3) mod 4.
struct Facet {
  int c;
  int i;
  int v[3];
};

V3 to_v3(const Point& p) { return V3(p.x(), p.y(), p.z()); }

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

// Normal of the oriented pair of triangles (a, b, u) and (a, b, z) around edge ab, as in the
// released Cocone code: +1 = flat continuation, -1 = folded onto each other.
double pair_cos(const V3& a, const V3& b, const V3& u, const V3& z) {
  const V3 n1 = (u - a).cross(b - a);
  const V3 n2 = (b - a).cross(z - a);
  const double n = n1.norm() * n2.norm();
  return n > 0 ? n1.dot(n2) / n : -1.0;
}

class Reconstructor {
 public:
  Reconstructor(const std::vector<Eigen::Vector3d>& input, const std::vector<V3>& normals,
                const CoconeParams& params)
      : input_(input), normals_(normals), prm_(params) {}

  Surface run();

 private:
  void deduplicate();
  void triangulate();
  void poles();
  void cocone_tests();
  void flatness();
  void candidates();
  void build_complex();
  bool umbrella(int v) const;
  void prune();
  void walk();
  std::vector<Face> oriented_facets() const;
  std::vector<double> component_scores(const std::vector<Face>& faces, const std::vector<std::uint8_t>& drop,
                                       const std::vector<int>& comp, int ncomp) const;
  Surface finish();

  // --- data ---
  const std::vector<Eigen::Vector3d>& input_;
  const std::vector<V3>& normals_;
  CoconeParams prm_;
  ReconstructStats st_;

  std::vector<int> row_of_;  // unique point id -> input row (first occurrence)
  std::vector<V3> p_;        // unique points
  std::vector<Point> cp_;
  Flat t_;
  std::vector<V3> cc_;     // circumcentre per finite cell
  std::vector<V3> hulln_;  // per infinite cell: outward unit normal of its finite facet
  std::vector<V3> axis_;   // unit pole axis per vertex
  std::vector<std::uint8_t> axis_ok_, on_hull_;
  std::vector<double> height2_;  // squared negative-pole distance (-1: none)
  std::vector<double> width2_;   // squared co-polygon width (inf: unbounded in the cocone)
  std::vector<Facet> facets_;
  std::vector<int> fidx_;            // 4c+i -> facet index or -1
  std::vector<std::uint8_t> meets_;  // per facet: bit s set when e_t meets the cocone of v[s]
  std::vector<std::uint8_t> flat_;
  std::vector<std::uint8_t> alive_;  // candidate flag per facet
  // candidate complex
  std::vector<int> cand_;  // candidate facet ids (ascending)
  std::vector<std::array<int, 2>> edges_;
  std::vector<int> edge_off_, edge_fac_;   // edge -> incident candidate facets
  std::vector<std::array<int, 3>> fedge_;  // facet -> edge opposite slot s (only candidates)
  std::vector<int> vf_off_, vf_fac_;       // vertex -> incident candidate facets
  std::vector<std::uint8_t> umb_, removable_;
  // walk
  std::vector<int> comp_, front_;
  std::vector<int> order_;  // accepted facets in acceptance order
  int components_ = 0;
};

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

void Reconstructor::poles() {
  const std::size_t n = p_.size();
  hulln_.assign(t_.cells, V3::Zero());
  on_hull_.assign(n, 0);
  std::vector<V3> sum(n, V3::Zero());
  for (int c = 0; c < t_.cells; ++c) {
    if (t_.finite(c)) continue;
    const int k = t_.local(c, kInfinite);
    const int a = t_.cv[4 * c + (k + 1) % 4];
    const int b = t_.cv[4 * c + (k + 2) % 4];
    const int d = t_.cv[4 * c + (k + 3) % 4];
    const int nb = t_.nbr[4 * c + k];
    const int o = t_.cv[4 * nb + t_.nbri[4 * c + k]];
    V3 nrm = (p_[b] - p_[a]).cross(p_[d] - p_[a]);
    if (nrm.dot(p_[o] - p_[a]) > 0) nrm = -nrm;
    const double len = nrm.norm();
    if (len > 0) nrm /= len;
    hulln_[c] = nrm;
    for (int v : {a, b, d}) {
      on_hull_[v] = 1;
      sum[v] += nrm;
    }
  }
  // Positive pole: farthest Voronoi vertex (bounded cells); hull samples: mean hull normal.
  std::vector<double> best(n, -1.0);
  axis_.assign(n, V3::Zero());
  for (int c = 0; c < t_.cells; ++c) {
    if (!t_.finite(c)) continue;
    for (int k = 0; k < 4; ++k) {
      const int v = t_.cv[4 * c + k];
      if (on_hull_[v]) continue;
      const V3 d = cc_[c] - p_[v];
      const double d2 = d.squaredNorm();
      if (d2 > best[v]) {
        best[v] = d2;
        axis_[v] = d;
      }
    }
  }
  axis_ok_.assign(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    if (on_hull_[v]) axis_[v] = sum[v];
    const double len = axis_[v].norm();
    if (len > 0 && std::isfinite(len)) {
      axis_[v] /= len;
      axis_ok_[v] = 1;
    } else {
      axis_[v] = V3::UnitZ();
    }
  }
  // Negative pole height: farthest Voronoi vertex on the other side of the pole axis.
  height2_.assign(n, -1.0);
  for (int c = 0; c < t_.cells; ++c) {
    if (!t_.finite(c)) continue;
    for (int k = 0; k < 4; ++k) {
      const int v = t_.cv[4 * c + k];
      const V3 d = cc_[c] - p_[v];
      if (d.dot(axis_[v]) < 0) height2_[v] = std::max(height2_[v], d.squaredNorm());
    }
  }
}

void Reconstructor::cocone_tests() {
  fidx_.assign(4 * static_cast<std::size_t>(t_.cells), -1);
  for (int c = 0; c < t_.cells; ++c) {
    for (int i = 0; i < 4; ++i) {
      const int n = t_.nbr[4 * c + i];
      const int j = t_.nbri[4 * c + i];
      if (4 * c + i > 4 * n + j) continue;  // the other representation is canonical
      Facet f{c, i, {t_.cv[4 * c + (i + 1) % 4], t_.cv[4 * c + (i + 2) % 4], t_.cv[4 * c + (i + 3) % 4]}};
      if (f.v[0] < 0 || f.v[1] < 0 || f.v[2] < 0) continue;
      fidx_[4 * c + i] = fidx_[4 * n + j] = static_cast<int>(facets_.size());
      facets_.push_back(f);
    }
  }
  const double tau = std::sin(prm_.cocone_angle);  // cos(pi/2 - theta)
  const double tau2 = tau * tau;
  const double inf = std::numeric_limits<double>::infinity();
  meets_.assign(facets_.size(), 0);
  width2_.assign(p_.size(), 0.0);
  for (std::size_t fi = 0; fi < facets_.size(); ++fi) {
    const Facet& f = facets_[fi];
    const int n = t_.nbr[4 * f.c + f.i];
    // Dual Voronoi edge: segment [a, b] or ray a + t·d.
    V3 a = V3::Zero(), b = V3::Zero(), d = V3::Zero();
    bool ray = false;
    if (!t_.finite(f.c)) {
      a = cc_[n];
      d = hulln_[f.c];
      ray = true;
    } else if (!t_.finite(n)) {
      a = cc_[f.c];
      d = hulln_[n];
      ray = true;
    } else {
      a = cc_[f.c];
      b = cc_[n];
    }
    for (int s = 0; s < 3; ++s) {
      const int v = f.v[s];
      const V3& nv = axis_[v];
      const V3 q = a - p_[v];
      const V3 r = ray ? d : V3(b - p_[v]);
      const double qn = q.dot(nv), rn = r.dot(nv);
      // Side of the cocone band (+1 upper polar cone, -1 lower, 0 inside), without a sqrt:
      // |cos| > tau  <=>  (x·n)^2 > tau^2 |x|^2.
      auto side = [tau2](double xn, const V3& x) {
        if (xn * xn <= tau2 * x.squaredNorm()) return 0;
        return xn > 0 ? 1 : -1;
      };
      const int sa = side(qn, q), sb = side(rn, r);
      if (!(sa != 0 && sa == sb)) meets_[fi] |= static_cast<std::uint8_t>(1u << s);
      if (!prm_.boundary_detection) continue;
      // Co-polygon width: farthest crossing of V_p's edges with the plane through p normal to
      // the pole axis; a ray running inside the cocone band makes the cocone unbounded.
      double w2 = -1.0;
      if (ray) {
        if (sb == 0) {
          w2 = inf;
        } else if (rn != 0 && -qn / rn >= 0) {
          w2 = (q + (-qn / rn) * d).squaredNorm();
        }
      } else if ((qn <= 0 && rn >= 0) || (qn >= 0 && rn <= 0)) {
        if (qn == rn) {
          w2 = std::max(q.squaredNorm(), r.squaredNorm());
        } else {
          const double t = qn / (qn - rn);
          w2 = (q + t * (r - q)).squaredNorm();
        }
      }
      width2_[v] = std::max(width2_[v], w2);
    }
  }
}

void Reconstructor::flatness() {
  const std::size_t n = p_.size();
  flat_.assign(n, 1);
  if (!prm_.boundary_detection) {
    st_.flat = st_.flat_seeds = n;
    return;
  }
  common::log::Phase phase("boundary");
  const double cos_alpha = std::cos(prm_.flat_angle);
  const double rho2 = prm_.flat_ratio * prm_.flat_ratio;
  std::vector<std::uint8_t> ratio_ok(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    ratio_ok[v] =
        axis_ok_[v] && height2_[v] > 0 && std::isfinite(width2_[v]) && width2_[v] <= rho2 * height2_[v];
  }
  // Cocone-neighbour pairs (p, q): q shares a Delaunay triangle with p whose dual edge meets
  // the cocone of p.
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(facets_.size() * 4);
  for (std::size_t fi = 0; fi < facets_.size(); ++fi) {
    const Facet& f = facets_[fi];
    for (int s = 0; s < 3; ++s) {
      if (!(meets_[fi] & (1u << s))) continue;
      pairs.emplace_back(f.v[s], f.v[(s + 1) % 3]);
      pairs.emplace_back(f.v[s], f.v[(s + 2) % 3]);
    }
  }
  auto aligned = [&](int p, int q) { return std::abs(axis_[p].dot(axis_[q])) >= cos_alpha; };
  std::vector<std::uint8_t> normal_ok(n, 1);
  for (const auto& [p, q] : pairs) {
    if (!aligned(p, q)) normal_ok[p] = 0;
  }
  std::size_t seeds = 0;
  std::vector<int> queue;
  for (std::size_t v = 0; v < n; ++v) {
    flat_[v] = ratio_ok[v] && normal_ok[v];
    if (flat_[v]) {
      ++seeds;
      queue.push_back(static_cast<int>(v));
    }
  }
  // Propagation: a sample meeting the ratio condition becomes flat when one of its cocone
  // neighbours is flat with an aligned pole. Reverse adjacency: q -> {p : q neighbour of p}.
  std::vector<int> off(n + 1, 0), rev(pairs.size());
  for (const auto& pq : pairs) ++off[pq.second + 1];
  for (std::size_t v = 0; v < n; ++v) off[v + 1] += off[v];
  {
    std::vector<int> fill(off.begin(), off.end() - 1);
    for (const auto& [p, q] : pairs) rev[fill[q]++] = p;
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int q = queue[head];
    for (int k = off[q]; k < off[q + 1]; ++k) {
      const int p = rev[k];
      if (flat_[p] || !ratio_ok[p] || !aligned(p, q)) continue;
      flat_[p] = 1;
      queue.push_back(p);
    }
  }
  st_.flat_seeds = seeds;
  st_.flat = queue.size();
  phase.done(std::to_string(st_.flat) + " of " + std::to_string(n) + " samples flat (" + std::to_string(seeds) +
             " before propagation), " + std::to_string(n - st_.flat) + " boundary/undersampled");
}

void Reconstructor::candidates() {
  alive_.assign(facets_.size(), 0);
  for (std::size_t fi = 0; fi < facets_.size(); ++fi) {
    const Facet& f = facets_[fi];
    int flats = 0;
    bool ok = true;
    for (int s = 0; s < 3; ++s) {
      if (!flat_[f.v[s]]) continue;
      ++flats;
      if (!(meets_[fi] & (1u << s))) ok = false;
    }
    if (flats > 0 && ok) {
      alive_[fi] = 1;
      cand_.push_back(static_cast<int>(fi));
    }
  }
  st_.candidates = cand_.size();
}

void Reconstructor::build_complex() {
  struct Entry {
    int a, b, f, s;
  };
  std::vector<Entry> es;
  es.reserve(cand_.size() * 3);
  for (int f : cand_) {
    const auto& v = facets_[f].v;
    for (int s = 0; s < 3; ++s) {
      int a = v[(s + 1) % 3], b = v[(s + 2) % 3];
      if (a > b) std::swap(a, b);
      es.push_back({a, b, f, s});
    }
  }
  std::sort(es.begin(), es.end(), [](const Entry& x, const Entry& y) {
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    return x.f < y.f;
  });
  fedge_.assign(facets_.size(), {-1, -1, -1});
  edge_off_.push_back(0);
  for (std::size_t k = 0; k < es.size(); ++k) {
    if (k == 0 || es[k].a != es[k - 1].a || es[k].b != es[k - 1].b) {
      if (k > 0) edge_off_.push_back(static_cast<int>(k));
      edges_.push_back({es[k].a, es[k].b});
    }
    edge_fac_.push_back(es[k].f);
    fedge_[es[k].f][es[k].s] = static_cast<int>(edges_.size()) - 1;
  }
  edge_off_.push_back(static_cast<int>(es.size()));
  if (edges_.empty()) edge_off_.assign(1, 0);

  const std::size_t n = p_.size();
  vf_off_.assign(n + 1, 0);
  for (int f : cand_)
    for (int v : facets_[f].v) ++vf_off_[v + 1];
  for (std::size_t v = 0; v < n; ++v) vf_off_[v + 1] += vf_off_[v];
  vf_fac_.resize(vf_off_[n]);
  std::vector<int> fill(vf_off_.begin(), vf_off_.end() - 1);
  for (int f : cand_)
    for (int v : facets_[f].v) vf_fac_[fill[v]++] = f;
}

// True when v has an umbrella in the current candidate complex: a cycle of candidate
// triangles around v in which every step to the next triangle (across an edge at v) turns
// the oriented normal by at most the sharp angle (released Cocone code's safety check).
bool Reconstructor::umbrella(int v) const {
  struct Item {
    int f, x, y;
  };
  std::vector<Item> items;
  for (int k = vf_off_[v]; k < vf_off_[v + 1]; ++k) {
    const int f = vf_fac_[k];
    if (!alive_[f]) continue;
    int o[2], m = 0;
    for (int w : facets_[f].v)
      if (w != v) o[m++] = w;
    items.push_back({f, o[0], o[1]});
  }
  if (items.size() < 3) return false;
  const double sharp_cos = std::cos(prm_.sharp_angle);
  const V3& pv = p_[v];
  auto other = [](const Item& it, int w) { return it.x == w ? it.y : it.x; };
  // Turn from triangle (v, at, other(cur, at)) to (v, at, other(next, at)) around edge v-at.
  auto smooth = [&](const Item& cur, const Item& next, int at) {
    return pair_cos(pv, p_[at], p_[other(cur, at)], p_[other(next, at)]) >= sharp_cos;
  };
  std::vector<int> marked;
  std::vector<std::pair<int, std::size_t>> stack;  // (item, next candidate index)
  for (std::size_t s0 = 0; s0 < items.size(); ++s0) {
    const int a0 = items[s0].x;
    marked.assign(1, items[s0].y);
    stack.assign(1, {static_cast<int>(s0), 0});
    std::vector<int> at_stack(1, items[s0].y);
    while (!stack.empty()) {
      auto& [cur, next] = stack.back();
      const int at = at_stack.back();
      if (next >= items.size()) {
        stack.pop_back();
        at_stack.pop_back();
        continue;
      }
      const std::size_t g = next++;
      if (static_cast<int>(g) == cur) continue;
      const Item& gi = items[g];
      if (gi.x != at && gi.y != at) continue;
      if (!smooth(items[cur], gi, at)) continue;
      const int y = other(gi, at);
      if (y == a0) {
        if (smooth(gi, items[s0], a0)) return true;
        continue;
      }
      if (std::find(marked.begin(), marked.end(), y) != marked.end()) continue;
      marked.push_back(y);
      const int gcur = static_cast<int>(g);
      stack.emplace_back(gcur, 0);
      at_stack.push_back(y);
    }
  }
  return false;
}

void Reconstructor::prune() {
  common::log::Phase phase("prune");
  const std::size_t n = p_.size();
  umb_.assign(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    if (vf_off_[v + 1] > vf_off_[v]) umb_[v] = umbrella(static_cast<int>(v));
  }
  const double sharp_cos = std::cos(prm_.sharp_angle);
  auto alive_at = [&](int e, std::vector<int>& out) {
    out.clear();
    for (int k = edge_off_[e]; k < edge_off_[e + 1]; ++k)
      if (alive_[edge_fac_[k]]) out.push_back(edge_fac_[k]);
  };
  auto third = [&](int f, int e) {
    for (int w : facets_[f].v)
      if (w != edges_[e][0] && w != edges_[e][1]) return w;
    return -1;
  };
  auto max_pair_cos = [&](int e, const std::vector<int>& fs) {
    double best = -2.0;
    const V3& a = p_[edges_[e][0]];
    const V3& b = p_[edges_[e][1]];
    for (std::size_t i = 0; i < fs.size(); ++i)
      for (std::size_t j = i + 1; j < fs.size(); ++j)
        best = std::max(best, pair_cos(a, b, p_[third(fs[i], e)], p_[third(fs[j], e)]));
    return best;
  };
  // Triangles at an edge with exactly two nearly coplanar candidates are never removed.
  removable_.assign(facets_.size(), 1);
  std::vector<int> fs;
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    alive_at(static_cast<int>(e), fs);
    if (fs.size() == 2 && max_pair_cos(static_cast<int>(e), fs) >= 0.7) {
      removable_[fs[0]] = removable_[fs[1]] = 0;
    }
  }
  auto eligible = [&](int e) {
    const int a = edges_[e][0], b = edges_[e][1];
    return flat_[a] && flat_[b] && umb_[a] && umb_[b];
  };
  std::vector<int> stack;
  for (int e = static_cast<int>(edges_.size()) - 1; e >= 0; --e)
    if (eligible(e)) stack.push_back(e);
  std::size_t pruned = 0;
  std::vector<int> removed, touched;
  while (!stack.empty()) {
    const int e = stack.back();
    stack.pop_back();
    if (!eligible(e)) continue;
    alive_at(e, fs);
    if (fs.empty()) continue;
    if (fs.size() > 1 && max_pair_cos(e, fs) >= sharp_cos) continue;
    removed.clear();
    for (int f : fs) {
      if (!removable_[f]) continue;
      alive_[f] = 0;
      removed.push_back(f);
      ++pruned;
    }
    touched.clear();
    for (int f : removed)
      for (int v : facets_[f].v) touched.push_back(v);
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    for (int v : touched) umb_[v] = umbrella(v);
    for (int f : removed)
      for (int e2 : fedge_[f])
        if (e2 != e && eligible(e2)) stack.push_back(e2);
  }
  st_.pruned = pruned;
  std::size_t umbrellas = 0;
  for (std::size_t v = 0; v < n; ++v) umbrellas += umb_[v];
  st_.umbrellas = umbrellas;
  phase.done(std::to_string(cand_.size()) + " candidate triangles, " + std::to_string(pruned) +
             " pruned at sharp edges, " + std::to_string(umbrellas) + " samples with an umbrella");
}

void Reconstructor::walk() {
  common::log::Phase phase("walk");
  comp_.assign(facets_.size(), -1);
  front_.assign(facets_.size(), -1);
  std::vector<std::uint8_t> tagged(p_.size(), 0);
  struct Oriented {
    int cell, k, f, a, b;  // facet f seen from cell (its front), rotating around edge a-b
  };
  std::vector<Oriented> stack;
  auto all_candidates = [&](int c) {
    for (int i = 0; i < 4; ++i) {
      const int g = fidx_[4 * c + i];
      if (g < 0 || !alive_[g]) return false;
    }
    return true;
  };
  auto accept = [&](int f, int cell, int k, int comp, int skip_a, int skip_b) {
    comp_[f] = comp;
    front_[f] = cell;
    order_.push_back(f);
    int lv[3], m = 0;
    for (int l = 0; l < 4; ++l)
      if (l != k) lv[m++] = l;
    for (int s = 0; s < 3; ++s) tagged[t_.cv[4 * cell + lv[s]]] = 1;
    for (int s = 0; s < 3; ++s) {
      const int a = t_.cv[4 * cell + lv[(s + 1) % 3]];
      const int b = t_.cv[4 * cell + lv[(s + 2) % 3]];
      if ((a == skip_a && b == skip_b) || (a == skip_b && b == skip_a)) continue;
      if (skip_a >= 0 && !(umb_[a] || umb_[b])) continue;
      stack.push_back({cell, k, f, a, b});
    }
  };
  for (int seed : cand_) {
    if (!alive_[seed] || comp_[seed] >= 0) continue;
    const Facet& fs = facets_[seed];
    if (tagged[fs.v[0]] || tagged[fs.v[1]] || tagged[fs.v[2]]) {
      alive_[seed] = 0;  // would pinch an existing component
      continue;
    }
    if (!umb_[fs.v[0]] || !umb_[fs.v[1]] || !umb_[fs.v[2]]) continue;
    const int other = t_.nbr[4 * fs.c + fs.i];
    if ((t_.finite(fs.c) && all_candidates(fs.c)) || (t_.finite(other) && all_candidates(other))) {
      continue;
    }
    const int comp = components_++;
    accept(seed, fs.c, fs.i, comp, -1, -1);
    while (!stack.empty()) {
      const Oriented o = stack.back();
      stack.pop_back();
      int cur = o.cell, k = o.k;
      bool found = false;
      for (int guard = 0; guard < 1 << 20; ++guard) {
        const int la = t_.local(cur, o.a), lb = t_.local(cur, o.b);
        const int j = 6 - k - la - lb;
        const int g = fidx_[4 * cur + j];
        if (g == o.f) break;
        if (g >= 0 && alive_[g]) {
          if (!found) {
            found = true;
            if (comp_[g] < 0) accept(g, cur, j, comp, o.a, o.b);
          } else if (comp_[g] < 0) {
            alive_[g] = 0;
          }
        }
        const int nxt = t_.nbr[4 * cur + j];
        k = t_.nbri[4 * cur + j];
        cur = nxt;
      }
    }
  }
  st_.components = static_cast<std::size_t>(components_);
  phase.done(std::to_string(order_.size()) + " triangles in " + std::to_string(components_) + " components");
}

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

}  // namespace

Surface reconstruct(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                    const CoconeParams& params) {
  if (!normals.empty() && normals.size() != points.size()) {
    throw common::Error("internal: " + std::to_string(normals.size()) + " normals for " +
                        std::to_string(points.size()) + " points");
  }
  if (points.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 8)) {
    throw common::Error("too many samples for one mesh: " + std::to_string(points.size()));
  }
  Reconstructor r(points, normals, params);
  return r.run();
}

}  // namespace canopy::cocone
