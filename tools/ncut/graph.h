// Sparse symmetric affinity graphs for normalized cuts: compressed rows, no self-loops,
// every weight > 0. Built from an edge list; subgraphs are induced on a vertex subset.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace canopy::ncut {

struct Edge {
  int a = 0, b = 0;  // vertex indices, a != b
  double w = 0;      // affinity > 0
};

class Graph {
 public:
  Graph() = default;
  // n vertices; each undirected edge listed once (either orientation). Duplicate (a, b) pairs
  // are an error (std::invalid_argument); edges with w <= 0 are dropped.
  Graph(int n, const std::vector<Edge>& edges);

  int size() const { return static_cast<int>(offset_.size()) - 1; }
  std::size_t edge_count() const { return nbr_.size() / 2; }
  // Neighbours of v in ascending order, with their weights.
  const int* nbr_begin(int v) const { return nbr_.data() + offset_[v]; }
  const int* nbr_end(int v) const { return nbr_.data() + offset_[v + 1]; }
  const double* w_begin(int v) const { return w_.data() + offset_[v]; }
  double degree(int v) const;  // d_v = sum of the weights at v

  // The subgraph induced on `vertices` (ascending, distinct); local index k = vertices[k].
  // `scratch` must hold size() entries of -1 and is left that way.
  Graph induced(const std::vector<int>& vertices, std::vector<int>* scratch) const;

  // Connected components over edges with w > 0; each component ascending, components
  // ordered by their smallest vertex.
  std::vector<std::vector<int>> components() const;

 private:
  std::vector<std::int64_t> offset_{0};
  std::vector<int> nbr_;
  std::vector<double> w_;
};

}  // namespace canopy::ncut
