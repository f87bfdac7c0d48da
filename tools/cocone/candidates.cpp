// Cocone steps 1-3 (shared spec ALGORITHMS.md §A): poles of every sample, the cocone test of
// every Delaunay facet (closed-form polar-cone test), Dey–Giesen flatness (co-polygon width vs
// negative-pole height, normal condition, propagation) and the bound-cocone candidate rule.

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "canopy/common/log.h"

#include "cocone/reconstructor.h"

namespace canopy::cocone::detail {

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

}  // namespace canopy::cocone::detail
