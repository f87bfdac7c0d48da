#include "ncut/cut.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Spectra/SymEigsSolver.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "canopy/common/error.h"
#include "canopy/common/log.h"

namespace canopy::ncut {
namespace {

using Eigen::VectorXd;

// Where the trivial eigenvector z0 is moved by the deflation: below every eigenvalue of N
// (which lie in [-1, 1]), so "largest algebraic" finds mu_2 even when mu_2 < 0.
constexpr double kDeflatedValue = -2.0;
// Shift of L_sym in shift-invert mode; keeps the factorisation SPD (L_sym is singular).
constexpr double kShiftEpsilon = 1e-6;
// A solve is accepted when ||N z - mu z|| stays below max(kResidualFloor, 100 * tolerance).
constexpr double kResidualFloor = 1e-8;
// Largest graph the dense solver takes as a last resort.
constexpr int kDenseFallbackMax = 3000;

struct Normalized {
  VectorXd s;   // d^-1/2
  VectorXd z0;  // D^1/2 1, unit
};

Normalized normalize(const Graph& g) {
  const int n = g.size();
  Normalized nm;
  nm.s.resize(n);
  nm.z0.resize(n);
  for (int v = 0; v < n; ++v) {
    const double d = g.degree(v);
    nm.s[v] = 1.0 / std::sqrt(d);
    nm.z0[v] = std::sqrt(d);
  }
  nm.z0.normalize();
  return nm;
}

// y = N x.
void apply_n(const Graph& g, const VectorXd& s, const double* x, double* y) {
  const int n = g.size();
  for (int v = 0; v < n; ++v) {
    const int* nb = g.nbr_begin(v);
    const int* ne = g.nbr_end(v);
    const double* w = g.w_begin(v);
    double acc = 0;
    for (; nb != ne; ++nb, ++w) acc += *w * s[*nb] * x[*nb];
    y[v] = s[v] * acc;
  }
}

class DeflatedOp {
 public:
  using Scalar = double;
  DeflatedOp(const Graph& g, const Normalized& nm) : g_(g), nm_(nm) {}
  Eigen::Index rows() const { return g_.size(); }
  Eigen::Index cols() const { return g_.size(); }
  void perform_op(const double* x, double* y) const {
    apply_n(g_, nm_.s, x, y);
    const Eigen::Map<const VectorXd> xv(x, g_.size());
    Eigen::Map<VectorXd> yv(y, g_.size());
    yv += (kDeflatedValue - 1.0) * nm_.z0.dot(xv) * nm_.z0;
  }

 private:
  const Graph& g_;
  const Normalized& nm_;
};

class ShiftInvertOp {
 public:
  using Scalar = double;
  ShiftInvertOp(const Graph& g, const Normalized& nm) : n_(g.size()), nm_(nm) {
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(2 * g.edge_count() + n_);
    for (int v = 0; v < n_; ++v) {
      t.emplace_back(v, v, 1.0 + kShiftEpsilon);
      const int* nb = g.nbr_begin(v);
      const double* w = g.w_begin(v);
      for (; nb != g.nbr_end(v); ++nb, ++w) t.emplace_back(v, *nb, -*w * nm.s[v] * nm.s[*nb]);
    }
    Eigen::SparseMatrix<double> m(n_, n_);
    m.setFromTriplets(t.begin(), t.end());
    ldlt_.compute(m);
    ok_ = ldlt_.info() == Eigen::Success;
  }
  bool ok() const { return ok_; }
  Eigen::Index rows() const { return n_; }
  Eigen::Index cols() const { return n_; }
  void perform_op(const double* x, double* y) const {
    const Eigen::Map<const VectorXd> xv(x, n_);
    Eigen::Map<VectorXd> yv(y, n_);
    const VectorXd px = xv - nm_.z0.dot(xv) * nm_.z0;
    yv = ldlt_.solve(px);
    yv -= nm_.z0.dot(yv) * nm_.z0;
  }

 private:
  int n_;
  const Normalized& nm_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  bool ok_ = false;
};

// Fills residual and mu from z (projected, unit); returns the residual.
double finish(const Graph& g, const Normalized& nm, EigenResult* r) {
  r->z -= nm.z0.dot(r->z) * nm.z0;
  const double norm = r->z.norm();
  if (!(norm > 0) || !std::isfinite(norm)) return INFINITY;
  r->z /= norm;
  VectorXd nz(g.size());
  apply_n(g, nm.s, r->z.data(), nz.data());
  r->mu = r->z.dot(nz);
  r->residual = (nz - r->mu * r->z).norm();
  return std::isfinite(r->residual) ? r->residual : INFINITY;
}

bool solve_dense(const Graph& g, const Normalized& nm, EigenResult* r) {
  const int n = g.size();
  Eigen::MatrixXd m = (kDeflatedValue - 1.0) * nm.z0 * nm.z0.transpose();
  for (int v = 0; v < n; ++v) {
    const int* nb = g.nbr_begin(v);
    const double* w = g.w_begin(v);
    for (; nb != g.nbr_end(v); ++nb, ++w) m(v, *nb) += *w * nm.s[v] * nm.s[*nb];
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m);
  if (es.info() != Eigen::Success) return false;
  r->z = es.eigenvectors().col(n - 1);  // eigenvalues ascending
  r->method = "dense";
  return true;
}

template <typename Op>
bool solve_spectra(Op& op, int n, int ncv, int maxit, double tol, EigenResult* r) {
  Spectra::SymEigsSolver<Op> es(op, 1, std::min(ncv, n));
  es.init();
  es.compute(Spectra::SortRule::LargestAlge, maxit, tol);
  r->matvecs += es.num_operations();
  r->restarts += es.num_iterations();
  if (es.info() != Spectra::CompInfo::Successful) return false;
  r->z = es.eigenvectors(1).col(0);
  return true;
}

const char* method_name(Solver s) {
  switch (s) {
    case Solver::kDense: return "dense";
    case Solver::kLanczos: return "lanczos";
    case Solver::kShiftInvert: return "shift-invert";
    default: return "auto";
  }
}

// One eigensolver attempt: the solver and its Lanczos basis size and restart limit.
struct Attempt {
  Solver solver;
  int ncv, maxit;
};

// The attempts in order: the configured one, then the fallbacks.
std::vector<Attempt> solver_attempts(int n, const CutParams& p) {
  Solver first = p.solver;
  if (first == Solver::kAuto) {
    // Shift-invert, not regular Lanczos: meshes give near-disconnected parts whose N has a
    // cluster of eigenvalues at 1, where regular mode crawls (docs/decisions/ncut.md).
    first = n <= p.dense_max ? Solver::kDense : Solver::kShiftInvert;
  }
  if (n < 3) first = Solver::kDense;  // Spectra needs nev < ncv <= n

  std::vector<Attempt> attempts{{first, p.ncv, p.max_restarts}};
  if (first != Solver::kDense && p.fallback) {
    if (first == Solver::kLanczos) attempts.push_back({Solver::kLanczos, 2 * p.ncv, 5 * p.max_restarts});
    attempts.push_back(
        {first == Solver::kLanczos ? Solver::kShiftInvert : Solver::kLanczos, 2 * p.ncv, 5 * p.max_restarts});
    if (n <= kDenseFallbackMax) attempts.push_back({Solver::kDense, 0, 0});
  }
  return attempts;
}

// Runs one attempt into r (z, method, counters); true when the solver converged.
bool run_attempt(const Graph& g, const Normalized& nm, const Attempt& a, double tolerance, EigenResult* r) {
  const int n = g.size();
  r->z.resize(0);
  if (a.solver == Solver::kDense) return solve_dense(g, nm, r);
  if (a.solver == Solver::kLanczos) {
    DeflatedOp op(g, nm);
    const bool ok = solve_spectra(op, n, a.ncv, a.maxit, tolerance, r);
    r->method = "lanczos";
    return ok;
  }
  ShiftInvertOp op(g, nm);
  const bool ok = op.ok() && solve_spectra(op, n, a.ncv, a.maxit, tolerance, r);
  r->method = "shift-invert";
  return ok;
}

// Appends why attempt a failed to the running list of failures.
void note_failure(const Attempt& a, bool ok, double res, std::string& failures) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "%s%s (ncv %d, maxit %d) %s", failures.empty() ? "" : "; ",
                method_name(a.solver), a.ncv, a.maxit,
                ok ? ("residual " + std::to_string(res) + " above bound").c_str() : "did not converge");
  failures += buf;
}

// Deterministic sign: the entry of largest magnitude (lowest index on ties) is positive.
void fix_sign(VectorXd& z) {
  Eigen::Index best = 0;
  for (Eigen::Index i = 1; i < z.size(); ++i) {
    if (std::abs(z[i]) > std::abs(z[best])) best = i;
  }
  if (z[best] < 0) z = -z;
}

void add_solve_stats(const EigenResult& r, CutStats* stats) {
  if (!stats) return;
  ++stats->solves;
  if (r.method == "dense") ++stats->dense_solves;
  if (r.method == "lanczos") ++stats->lanczos_solves;
  if (r.method == "shift-invert") ++stats->shift_invert_solves;
  stats->matvecs += r.matvecs;
  stats->restarts += r.restarts;
  stats->max_matvecs = std::max(stats->max_matvecs, r.matvecs);
  stats->max_residual = std::max(stats->max_residual, r.residual);
}

}  // namespace

EigenResult second_eigenvector(const Graph& g, const CutParams& p, CutStats* stats) {
  const int n = g.size();
  if (n < 2) throw std::invalid_argument("second_eigenvector: graph has fewer than 2 vertices");
  const Normalized nm = normalize(g);
  const double bound = std::max(kResidualFloor, 100 * p.tolerance);
  const std::vector<Attempt> attempts = solver_attempts(n, p);

  EigenResult r;
  std::string failures;
  for (std::size_t k = 0; k < attempts.size(); ++k) {
    const Attempt& a = attempts[k];
    const bool ok = run_attempt(g, nm, a, p.tolerance, &r);
    const double res = ok ? finish(g, nm, &r) : INFINITY;
    if (ok && res <= bound) {
      if (k > 0) {
        if (stats) ++stats->fallbacks;
        common::log::warn("ncut eigensolve on " + std::to_string(n) + " vertices: " + failures +
                          "; fell back to " + r.method + " (ncv " + std::to_string(a.ncv) + "), converged");
      }
      break;
    }
    note_failure(a, ok, res, failures);
    if (k + 1 == attempts.size()) {
      throw common::Error("normalized cut eigensolver failed on a part of " + std::to_string(n) +
                          " vertices: " + failures +
                          " (try another solver, tolerance, restart limit or Lanczos basis size)");
    }
  }
  fix_sign(r.z);
  add_solve_stats(r, stats);
  return r;
}

double ncut_value(const Graph& g, const std::vector<char>& in_a) {
  double cut = 0, vol_a = 0, vol_b = 0;
  for (int v = 0; v < g.size(); ++v) {
    const int* nb = g.nbr_begin(v);
    const double* w = g.w_begin(v);
    for (; nb != g.nbr_end(v); ++nb, ++w) {
      (in_a[v] ? vol_a : vol_b) += *w;
      if (in_a[v] && !in_a[*nb]) cut += *w;
    }
  }
  if (!(vol_a > 0) || !(vol_b > 0)) return cut > 0 ? INFINITY : 0.0;
  return cut / vol_a + cut / vol_b;
}

SweepCut best_sweep_cut(const Graph& g, const VectorXd& y, int min_size) {
  const int n = g.size();
  min_size = std::max(min_size, 1);
  SweepCut out;
  if (n < 2 * min_size) return out;
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return y[a] < y[b] || (y[a] == y[b] && a < b); });
  std::vector<double> d(n);
  for (int v = 0; v < n; ++v) d[v] = g.degree(v);
  // Suffix volumes, so that vol(B) is not a difference of two large sums.
  std::vector<double> vol_after(n + 1, 0.0);
  for (int k = n - 1; k >= 0; --k) vol_after[k] = vol_after[k + 1] + d[order[k]];

  std::vector<char> in_a(n, 0);
  double cut = 0, vol_a = 0, best = INFINITY;
  int best_k = -1;
  for (int k = 0; k + 1 < n; ++k) {
    const int v = order[k];
    double to_a = 0;
    const int* nb = g.nbr_begin(v);
    const double* w = g.w_begin(v);
    for (; nb != g.nbr_end(v); ++nb, ++w) {
      if (in_a[*nb]) to_a += *w;
    }
    in_a[v] = 1;
    cut += d[v] - 2 * to_a;
    vol_a += d[v];
    const int size_a = k + 1;
    if (y[order[k]] == y[order[k + 1]] || size_a < min_size || n - size_a < min_size) continue;
    const double c = std::max(cut, 0.0);
    const double value = c / vol_a + c / vol_after[k + 1];
    if (value < best) {
      best = value;
      best_k = k;
    }
  }
  if (best_k < 0) return out;
  out.found = true;
  out.in_a.assign(n, 0);
  for (int k = 0; k <= best_k; ++k) out.in_a[order[k]] = 1;
  out.ncut = ncut_value(g, out.in_a);
  return out;
}

std::vector<int> recursive_ncut(const Graph& g, const CutParams& p, CutStats* stats) {
  const int n = g.size();
  CutStats local;
  CutStats& st = stats ? *stats : local;
  const int min_size = std::max(p.min_segment, 1);
  std::vector<std::vector<int>> leaves;
  std::vector<std::vector<int>> stack = g.components();
  st.components = static_cast<int>(stack.size());
  std::reverse(stack.begin(), stack.end());
  std::vector<int> scratch(n, -1);
  while (!stack.empty()) {
    std::vector<int> part = std::move(stack.back());
    stack.pop_back();
    const int m = static_cast<int>(part.size());
    if (m < 2 * min_size || m < 2) {
      leaves.push_back(std::move(part));
      continue;
    }
    const Graph sub = g.induced(part, &scratch);
    auto comps = sub.components();
    if (comps.size() > 1) {
      // A cut can leave a side disconnected: its pieces separate at Ncut = 0.
      for (auto it = comps.rbegin(); it != comps.rend(); ++it) {
        std::vector<int> piece;
        piece.reserve(it->size());
        for (int l : *it) piece.push_back(part[l]);
        stack.push_back(std::move(piece));
      }
      continue;
    }
    const EigenResult e = second_eigenvector(sub, p, &st);
    VectorXd y(m);
    for (int v = 0; v < m; ++v) y[v] = e.z[v] / std::sqrt(sub.degree(v));
    const SweepCut cut = best_sweep_cut(sub, y, min_size);
    if (!cut.found || !(cut.ncut < p.max_ncut)) {
      ++st.rejected;
      leaves.push_back(std::move(part));
      continue;
    }
    ++st.splits;
    std::vector<int> a, b;
    for (int v = 0; v < m; ++v) (cut.in_a[v] ? a : b).push_back(part[v]);
    stack.push_back(std::move(b));
    stack.push_back(std::move(a));
  }
  std::sort(leaves.begin(), leaves.end(),
            [](const std::vector<int>& a, const std::vector<int>& b) { return a[0] < b[0]; });
  std::vector<int> label(n, -1);
  for (std::size_t k = 0; k < leaves.size(); ++k) {
    for (int v : leaves[k]) label[v] = static_cast<int>(k);
  }
  return label;
}

}  // namespace canopy::ncut
