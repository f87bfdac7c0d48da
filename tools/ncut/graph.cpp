#include "ncut/graph.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace canopy::ncut {

Graph::Graph(int n, const std::vector<Edge>& edges) {
  std::vector<std::int64_t> count(static_cast<std::size_t>(n) + 1, 0);
  for (const Edge& e : edges) {
    if (e.a < 0 || e.b < 0 || e.a >= n || e.b >= n || e.a == e.b) {
      throw std::invalid_argument("graph edge (" + std::to_string(e.a) + ", " + std::to_string(e.b) +
                                  ") is a self-loop or out of range");
    }
    if (!(e.w > 0)) continue;
    ++count[e.a + 1];
    ++count[e.b + 1];
  }
  std::partial_sum(count.begin(), count.end(), count.begin());
  offset_ = count;
  nbr_.resize(offset_.back());
  w_.resize(offset_.back());
  std::vector<std::int64_t> fill(offset_.begin(), offset_.end() - 1);
  for (const Edge& e : edges) {
    if (!(e.w > 0)) continue;
    nbr_[fill[e.a]] = e.b;
    w_[fill[e.a]++] = e.w;
    nbr_[fill[e.b]] = e.a;
    w_[fill[e.b]++] = e.w;
  }
  // Sort each row by neighbour so that every later traversal is order-independent.
  std::vector<std::pair<int, double>> row;
  for (int v = 0; v < n; ++v) {
    const std::int64_t lo = offset_[v], hi = offset_[v + 1];
    row.clear();
    for (std::int64_t k = lo; k < hi; ++k) row.emplace_back(nbr_[k], w_[k]);
    std::sort(row.begin(), row.end());
    for (std::int64_t k = lo; k < hi; ++k) {
      if (k > lo && row[k - lo].first == row[k - lo - 1].first) {
        throw std::invalid_argument("graph edge (" + std::to_string(v) + ", " +
                                    std::to_string(row[k - lo].first) + ") listed twice");
      }
      nbr_[k] = row[k - lo].first;
      w_[k] = row[k - lo].second;
    }
  }
}

double Graph::degree(int v) const {
  double d = 0;
  for (std::int64_t k = offset_[v]; k < offset_[v + 1]; ++k) d += w_[k];
  return d;
}

Graph Graph::induced(const std::vector<int>& vertices, std::vector<int>* scratch) const {
  std::vector<int>& local = *scratch;
  const int m = static_cast<int>(vertices.size());
  for (int k = 0; k < m; ++k) local[vertices[k]] = k;
  Graph g;
  g.offset_.assign(static_cast<std::size_t>(m) + 1, 0);
  for (int k = 0; k < m; ++k) {
    const int v = vertices[k];
    std::int64_t c = 0;
    for (std::int64_t e = offset_[v]; e < offset_[v + 1]; ++e) c += local[nbr_[e]] >= 0;
    g.offset_[k + 1] = g.offset_[k] + c;
  }
  g.nbr_.resize(g.offset_.back());
  g.w_.resize(g.offset_.back());
  for (int k = 0; k < m; ++k) {
    const int v = vertices[k];
    std::int64_t out = g.offset_[k];
    // Rows stay sorted: `vertices` is ascending, so local order follows global order.
    for (std::int64_t e = offset_[v]; e < offset_[v + 1]; ++e) {
      const int l = local[nbr_[e]];
      if (l < 0) continue;
      g.nbr_[out] = l;
      g.w_[out++] = w_[e];
    }
  }
  for (int v : vertices) local[v] = -1;
  return g;
}

std::vector<std::vector<int>> Graph::components() const {
  const int n = size();
  std::vector<int> comp(n, -1);
  std::vector<std::vector<int>> out;
  std::vector<int> stack;
  for (int s = 0; s < n; ++s) {
    if (comp[s] >= 0) continue;
    const int id = static_cast<int>(out.size());
    out.emplace_back();
    comp[s] = id;
    stack.push_back(s);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      out[id].push_back(v);
      for (std::int64_t e = offset_[v]; e < offset_[v + 1]; ++e) {
        const int u = nbr_[e];
        if (comp[u] < 0 && w_[e] > 0) {
          comp[u] = id;
          stack.push_back(u);
        }
      }
    }
    std::sort(out[id].begin(), out[id].end());
  }
  return out;
}

}  // namespace canopy::ncut
