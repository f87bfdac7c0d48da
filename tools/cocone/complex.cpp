// The candidate complex: umbrellas, pruning of sharp edges between flat samples with
// umbrellas (never across holes: the cascade guard), and the orientation-consistent walk that
// accepts the surface triangles component by component.

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "canopy/common/log.h"

#include "cocone/reconstructor.h"

namespace canopy::cocone::detail {

namespace {

// Normal of the oriented pair of triangles (a, b, u) and (a, b, z) around edge ab, as in the
// released Cocone code: +1 = flat continuation, -1 = folded onto each other.
double pair_cos(const V3& a, const V3& b, const V3& u, const V3& z) {
  const V3 n1 = (u - a).cross(b - a);
  const V3 n2 = (b - a).cross(z - a);
  const double n = n1.norm() * n2.norm();
  return n > 0 ? n1.dot(n2) / n : -1.0;
}

}  // namespace

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

}  // namespace canopy::cocone::detail
