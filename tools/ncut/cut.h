// Recursive two-way normalized cuts (Shi & Malik 2000; thesis 5.2.2-5.3) on a sparse
// affinity graph. Connected components are split off first (Ncut = 0, no eigensolve);
// each connected part is cut at the best threshold of y = D^-1/2 z, z the second
// eigenvector of N = D^-1/2 A D^-1/2, while the cut's Ncut stays below max_ncut.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "ncut/graph.h"

namespace canopy::ncut {

enum class Solver {
  kAuto,         // dense up to dense_max vertices, else shift-invert
  kDense,        // Eigen::SelfAdjointEigenSolver on the dense N (small graphs only)
  kLanczos,      // Spectra SymEigsSolver on N - 3 z0 z0^T (z0 = trivial eigenvector), regular mode
  kShiftInvert,  // Spectra SymEigsSolver on P (L_sym + eps I)^-1 P, SimplicialLDLT
};

struct CutParams {
  double max_ncut = 0.1;  // split only while Ncut < max_ncut (thesis 5.6)
  int min_segment = 1;    // no split leaves a side with fewer vertices
  Solver solver = Solver::kAuto;
  double tolerance = 1e-10;  // Spectra's relative Ritz tolerance
  int max_restarts = 1000;   // Spectra's maxit
  int ncv = 20;              // Lanczos basis size
  int dense_max = 64;        // kAuto: dense solver at or below this size
  bool fallback = true;      // on non-convergence try other settings/methods before failing
};

struct CutStats {
  int components = 0;  // connected components of the whole graph
  int splits = 0;      // accepted two-way cuts
  int rejected = 0;    // parts whose best cut had Ncut >= max_ncut
  int solves = 0;      // eigen-solves, by method:
  int dense_solves = 0, lanczos_solves = 0, shift_invert_solves = 0;
  int fallbacks = 0;          // solves that needed a second method or setting
  long long matvecs = 0;      // operator applications of all iterative solves
  long long restarts = 0;     // Spectra restart iterations of all iterative solves
  long long max_matvecs = 0;  // of one solve
  double max_residual = 0;    // max ||N z - mu z|| over accepted eigenvectors
};

struct EigenResult {
  Eigen::VectorXd z;  // unit eigenvector of N, orthogonal to D^1/2 1, sign fixed
  double mu = 0;      // its eigenvalue (1 - lambda_2 of L_sym)
  double residual = 0;
  std::string method;
  long long matvecs = 0, restarts = 0;
};

// Second eigenvector of N for a connected graph with >= 2 vertices. Tries the configured
// method, then falls back (logging a warning); throws canopy::common::Error when no method
// reaches the residual bound.
EigenResult second_eigenvector(const Graph& g, const CutParams& params, CutStats* stats);

struct SweepCut {
  bool found = false;
  double ncut = 0;         // exact Ncut of the chosen partition
  std::vector<char> in_a;  // side per vertex (1 = the low-y side)
};

// Best Ncut over every threshold between distinct values of y (ties move together),
// keeping >= min_size vertices per side.
SweepCut best_sweep_cut(const Graph& g, const Eigen::VectorXd& y, int min_size);

// Ncut(A, B) = cut/assoc(A, V) + cut/assoc(B, V) (Eq. 5.5).
double ncut_value(const Graph& g, const std::vector<char>& in_a);

// Segment label per vertex: labels 0..k-1 numbered by each segment's smallest vertex.
std::vector<int> recursive_ncut(const Graph& g, const CutParams& params, CutStats* stats);

}  // namespace canopy::ncut
