// Pairwise affinities between oriented surface points, and the sparse affinity graph of a
// mesh (thesis ch. 5.3). The affinity is an interface so that variants (the probabilistic
// affinities of thesis 5.4, other normalisations) can be swapped in without touching the cut.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ncut/graph.h"

namespace canopy::ncut {

// Oriented points: positions (m, world frame) and unit normals (a zero normal = unknown).
struct SurfacePoints {
  std::vector<Eigen::Vector3d> p;
  std::vector<Eigen::Vector3d> n;
};

// A symmetric affinity in [0, 1]: A(i, j) == A(j, i).
class Affinity {
 public:
  virtual ~Affinity() = default;
  virtual double operator()(int i, int j) const = 0;
  virtual std::string name() const = 0;
  // No affinity between points farther apart than this (m): the graph's cut-off.
  virtual double radius() const = 0;
};

// How the printed exponents treat their distances.
//  kLinear:  exp(-theta / (2 sigma_n^2)) * exp(-d_mm / (2 r_mm^2)), Eq. 5.11 as printed
//            (theta in radians; lengths in millimetres, the thesis's unit, because the
//            unsquared form is not unit-free).
//  kSquared: exp(-theta^2 / (2 sigma_n^2)) * exp(-d^2 / (2 r^2)), the general form Eq. 5.1.
enum class Exponent { kLinear, kSquared };

struct ThesisAffinityParams {
  double sigma_n = 0.17453292519943295;  // rad (10 deg)
  double anisotropy = 2.0;               // E >= 1 of Eq. 5.8
  double radius = 0.512;                 // r (m)
  Exponent exponent = Exponent::kLinear;
};

// Eq. 5.8 one-sided anisotropic distance from p_i (with normal n_i) to p_j:
// sqrt(E (v.n_i)^2 + |v - (v.n_i) n_i|^2 / E), v = p_i - p_j.
double anisotropic_distance(const Eigen::Vector3d& pi, const Eigen::Vector3d& ni, const Eigen::Vector3d& pj,
                            double anisotropy);

// Eq. 5.11 / 5.12: A_ij = min(a_ij, a_ji). Keeps a reference to `points`.
class ThesisAffinity : public Affinity {
 public:
  ThesisAffinity(const SurfacePoints& points, const ThesisAffinityParams& params);
  double operator()(int i, int j) const override;
  // The one-sided a_ij of Eq. 5.11.
  double one_sided(int i, int j) const;
  std::string name() const override;
  double radius() const override { return prm_.radius; }

 private:
  double exponent_of(double theta, double d) const;
  const SurfacePoints& pts_;
  ThesisAffinityParams prm_;
};

// Sparsification of thesis 5.3.
struct SparsifyParams {
  double dense_radius = 0.175;  // beyond this distance only a random share is kept (m)
  double keep_fraction = 0.25;  // that share
  double min_affinity = 0.1;    // affinities below are dropped
  bool keep_mesh_edges = true;  // mesh neighbours are kept whatever their distance/affinity
  // Forced mesh-neighbour affinities are raised to at least this, so the graph is numerically
  // connected: weights of 1e-30 across a crease make lambda_2 of L_sym smaller than any usable
  // shift and the eigensolvers stall (docs/decisions/ncut.md). 0 = keep them as computed.
  double mesh_edge_floor = 1e-3;
  std::uint64_t seed = 1;  // the random share is a function of (seed, i, j) only
};

struct GraphStats {
  std::size_t pairs_within_radius = 0;  // point pairs with distance <= radius
  std::size_t dropped_random = 0;
  std::size_t dropped_small = 0;
  std::size_t mesh_edges = 0;
  std::size_t mesh_edges_forced = 0;  // mesh edges that the rules above would have dropped
  std::size_t edges = 0;              // edges of the final graph (w > 0)
};

// Builds the sparse affinity graph over all points: pairs within affinity.radius(). `mesh_edges` are the
// undirected edges of the mesh (a < b, unique).
Graph build_affinity_graph(const SurfacePoints& points, const std::vector<std::array<int, 2>>& mesh_edges,
                           const Affinity& affinity, const SparsifyParams& params, GraphStats* stats = nullptr);

}  // namespace canopy::ncut
