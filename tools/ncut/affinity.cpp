#include "ncut/affinity.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "canopy/common/rng.h"

namespace canopy::ncut {
namespace {

// The printed Eq. 5.11 is evaluated in millimetres (see Exponent::kLinear).
constexpr double kThesisUnitsPerMetre = 1000.0;

// Uniform [0, 1) from (seed, i, j), i < j: the same pair gets the same draw whatever the
// traversal order or thread count.
double pair_uniform(std::uint64_t seed, int i, int j) {
  const std::uint64_t key =
      (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
  return static_cast<double>(common::mix64(common::mix64(seed) ^ key) >> 11) * 0x1.0p-53;
}

}  // namespace

double anisotropic_distance(const Eigen::Vector3d& pi, const Eigen::Vector3d& ni, const Eigen::Vector3d& pj,
                            double anisotropy) {
  const Eigen::Vector3d v = pi - pj;
  const double a = v.dot(ni);
  const double t2 = std::max(0.0, (v - a * ni).squaredNorm());
  return std::sqrt(anisotropy * a * a + t2 / anisotropy);
}

ThesisAffinity::ThesisAffinity(const SurfacePoints& points, const ThesisAffinityParams& params)
    : pts_(points), prm_(params) {}

double ThesisAffinity::exponent_of(double theta, double d) const {
  const double s2 = 2 * prm_.sigma_n * prm_.sigma_n;
  if (prm_.exponent == Exponent::kSquared) {
    return theta * theta / s2 + d * d / (2 * prm_.radius * prm_.radius);
  }
  const double r_units = prm_.radius * kThesisUnitsPerMetre;
  return theta / s2 + d * kThesisUnitsPerMetre / (2 * r_units * r_units);
}

double ThesisAffinity::one_sided(int i, int j) const {
  const double c = std::clamp(pts_.n[i].dot(pts_.n[j]), -1.0, 1.0);
  const double d = anisotropic_distance(pts_.p[i], pts_.n[i], pts_.p[j], prm_.anisotropy);
  return std::exp(-exponent_of(std::acos(c), d));
}

double ThesisAffinity::operator()(int i, int j) const {
  // The normal term is symmetric, so min(a_ij, a_ji) takes the larger one-sided distance.
  const double c = std::clamp(pts_.n[i].dot(pts_.n[j]), -1.0, 1.0);
  const double d = std::max(anisotropic_distance(pts_.p[i], pts_.n[i], pts_.p[j], prm_.anisotropy),
                            anisotropic_distance(pts_.p[j], pts_.n[j], pts_.p[i], prm_.anisotropy));
  return std::exp(-exponent_of(std::acos(c), d));
}

std::string ThesisAffinity::name() const {
  return prm_.exponent == Exponent::kSquared ? "thesis-5.11-squared" : "thesis-5.11-linear";
}

namespace {

// Uniform grid of cell = radius over the points; vertices sorted by cell key for range lookups.
class CellGrid {
 public:
  CellGrid(const std::vector<Eigen::Vector3d>& p, double cell) : cell_(cell) {
    const int n = static_cast<int>(p.size());
    if (n > 0) {
      lo_ = p[0];
      for (const auto& q : p) lo_ = lo_.cwiseMin(q);
    }
    order_.resize(n);
    for (int i = 0; i < n; ++i) {
      const auto c = cell_of(p[i]);
      order_[i] = {key_of(c[0], c[1], c[2]), i};
    }
    std::sort(order_.begin(), order_.end());
  }
  std::array<std::int64_t, 3> cell_of(const Eigen::Vector3d& p) const {
    std::array<std::int64_t, 3> c{};
    for (int k = 0; k < 3; ++k) {
      const double f = std::floor((p[k] - lo_[k]) / cell_) + 1;
      if (!(f < kSpan - 2)) { throw std::runtime_error("point set extent exceeds 2^20 affinity radii"); }
      c[k] = static_cast<std::int64_t>(f);
    }
    return c;
  }
  static std::int64_t key_of(std::int64_t x, std::int64_t y, std::int64_t z) {
    return (x * kSpan + y) * kSpan + z;
  }
  // Calls visit(j) for every vertex j > i in the cell with this key, j ascending.
  template <class Visit>
  void for_each_after(std::int64_t key, int i, Visit&& visit) const {
    auto it = std::lower_bound(order_.begin(), order_.end(), std::make_pair(key, i + 1));
    for (; it != order_.end() && it->first == key; ++it) visit(it->second);
  }

 private:
  // Cell coordinates start at 1 so that every neighbour cell is >= 0 and keys never alias.
  static constexpr std::int64_t kSpan = 1 << 20;
  double cell_;
  Eigen::Vector3d lo_ = Eigen::Vector3d::Constant(0);
  std::vector<std::pair<std::int64_t, int>> order_;
};

// Mesh adjacency, rows ascending, for the "always keep" rule.
std::vector<std::vector<int>> mesh_adjacency(int n, const std::vector<std::array<int, 2>>& mesh_edges) {
  std::vector<std::vector<int>> adj(n);
  for (const auto& e : mesh_edges) {
    adj[e[0]].push_back(e[1]);
    adj[e[1]].push_back(e[0]);
  }
  for (auto& row : adj) std::sort(row.begin(), row.end());
  return adj;
}

// The sparsification rule for one pair i < j within the radius: appends the kept edge.
void consider_pair(int i, int j, double dist2, bool mesh, const Affinity& affinity, const SparsifyParams& prm,
                   std::vector<Edge>& edges, GraphStats& st) {
  const double dense2 = prm.dense_radius * prm.dense_radius;
  ++st.pairs_within_radius;
  if (!mesh && dist2 > dense2 && pair_uniform(prm.seed, i, j) >= prm.keep_fraction) {
    ++st.dropped_random;
    return;
  }
  const double a = affinity(i, j);
  if (!mesh && a < prm.min_affinity) {
    ++st.dropped_small;
    return;
  }
  if (mesh && (a < prm.min_affinity || (dist2 > dense2 && pair_uniform(prm.seed, i, j) >= prm.keep_fraction))) {
    ++st.mesh_edges_forced;
  }
  edges.push_back({i, j, mesh ? std::max(a, prm.mesh_edge_floor) : a});
}

}  // namespace

Graph build_affinity_graph(const SurfacePoints& points, const std::vector<std::array<int, 2>>& mesh_edges,
                           const Affinity& affinity, const SparsifyParams& prm, GraphStats* stats) {
  const int n = static_cast<int>(points.p.size());
  GraphStats st;
  st.mesh_edges = mesh_edges.size();
  const std::vector<std::vector<int>> adj = mesh_adjacency(n, mesh_edges);
  auto is_mesh_edge = [&](int i, int j) { return std::binary_search(adj[i].begin(), adj[i].end(), j); };
  const CellGrid grid(points.p, affinity.radius());

  const double r2 = affinity.radius() * affinity.radius();
  std::vector<Edge> edges;
  for (int i = 0; i < n; ++i) {
    const auto c = grid.cell_of(points.p[i]);
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          grid.for_each_after(CellGrid::key_of(c[0] + dx, c[1] + dy, c[2] + dz), i, [&](int j) {
            const double dist2 = (points.p[i] - points.p[j]).squaredNorm();
            if (dist2 > r2) return;
            const bool mesh = prm.keep_mesh_edges && is_mesh_edge(i, j);
            consider_pair(i, j, dist2, mesh, affinity, prm, edges, st);
          });
        }
      }
    }
  }
  // Mesh edges longer than the radius were not visited above.
  if (prm.keep_mesh_edges) {
    for (const auto& e : mesh_edges) {
      if ((points.p[e[0]] - points.p[e[1]]).squaredNorm() > r2) {
        edges.push_back({e[0], e[1], std::max(affinity(e[0], e[1]), prm.mesh_edge_floor)});
        ++st.mesh_edges_forced;
      }
    }
  }
  Graph g(n, edges);
  st.edges = g.edge_count();
  if (stats) *stats = st;
  return g;
}

}  // namespace canopy::ncut
