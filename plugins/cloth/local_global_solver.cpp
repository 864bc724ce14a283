#include <cmath>

#include <Eigen/SparseCore>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "implicit_solvers.hpp"
#include "incremental_potential.hpp"

namespace loom::cloth {
namespace {
// Plain local/global iterations before Chebyshev acceleration starts (Wang's
// S): the nonlinear local step settles first.
constexpr int kChebyshevDelay = 4;
}  // namespace

LocalGlobalSolver::LocalGlobalSolver(const SpringSystem& s, double h, double contact_weight)
    : h_(h), contact_weight_(contact_weight) {
  row_.assign(s.vertices(), -1);
  for (int i = 0; i < s.vertices(); ++i)
    if (!s.fixed[i]) {
      row_[i] = static_cast<int>(free_.size());
      free_.push_back(i);
    }
  const int n = static_cast<int>(free_.size());
  if (n == 0) return;
  // M + h² L with L = Σ_s k_s A_s A_sᵀ (A_s = e_s1 − e_s2), restricted to the
  // free vertices; the same 1-D matrix serves x, y and z.
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(n) + 4 * static_cast<size_t>(s.spring_count()));
  for (int r = 0; r < n; ++r) t.emplace_back(r, r, s.mass[free_[r]] + h * h * contact_weight);
  for (Eigen::Index k = 0; k < s.springs.rows(); ++k) {
    const int a = row_[s.springs(k, 0)], b = row_[s.springs(k, 1)];
    const double w = h * h * s.stiffness[k];
    if (a >= 0) t.emplace_back(a, a, w);
    if (b >= 0) t.emplace_back(b, b, w);
    if (a >= 0 && b >= 0) {
      t.emplace_back(a, b, -w);
      t.emplace_back(b, a, -w);
    }
  }
  loom::numerics::SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  cholesky_.compute(A);
}

// Over 80 lines on purpose: Liu et al. (2013)'s iteration read as one loop,
// local step, global solve and the convergence measure side by side.
Eigen::MatrixX3d LocalGlobalSolver::solve(const SpringSystem& s, const Eigen::MatrixX3d& y,
                                          Eigen::MatrixX3d x, const SolveOptions& options,
                                          SolveReport* report) const {
  SolveReport local;
  SolveReport& rep = report ? *report : local;
  rep = {};
  const int n = static_cast<int>(free_.size());
  if (n == 0) {
    rep.converged = true;
    return x;
  }
  const double h2 = h_ * h_;
  const bool measure = options.record_residuals || options.tolerance > 0;
  const double g0 = measure ? incremental_gradient(s, x, y, h_).norm() : 1;
  if (measure && g0 == 0) {
    rep.converged = true;
    return x;
  }
  const Eigen::Index m = s.springs.rows();
  Eigen::MatrixX3d excess(m, 3);  // r_s − d_s
  Eigen::MatrixX3d previous = x;  // x_{k−1} for Chebyshev
  const bool contacts = contact_weight_ > 0 && options.contact_target;
  Eigen::MatrixX3d target;  // contact projections p_i (Projective Dynamics)
  double omega = 1;
  const double rho = options.chebyshev_rho;
  for (int it = 0; it < options.iterations; ++it) {
    // Local step (eq. 12): r_s − d_s with d_s = l_s r_s/‖r_s‖ the rest-length
    // vector along each spring.
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, m, 4096), [&](const auto& range) {
      for (Eigen::Index k = range.begin(); k != range.end(); ++k) {
        const Eigen::RowVector3d r = x.row(s.springs(k, 0)) - x.row(s.springs(k, 1));
        const double len = r.norm();
        // Coincident ends: d_s = 0 (the nearest point of the rest sphere is
        // undefined there, and any choice leaves E unchanged).
        excess.row(k) = len > 0 ? Eigen::RowVector3d((1 - s.rest_length[k] / len) * r) : r;
      }
    });
    if (contacts) options.contact_target(x, target);
    // Global step (eq. 10), (M + h² L) x = M y + h² J d, solved for the
    // change Δ = x_{k+1} − x_k: (M + h² L) Δ = M (y − x_k) − h² Σ_s k_s A_s (r_s − d_s)ᵀ.
    // The right-hand side is small near convergence and computed without
    // cancellation, so Δ keeps full relative accuracy however large x is
    // (fixed neighbours enter through r_s).
    Eigen::MatrixX3d rhs(n, 3);
    for (int r = 0; r < n; ++r) rhs.row(r) = s.mass[free_[r]] * (y.row(free_[r]) - x.row(free_[r]));
    // Contact constraints: + h² w (p_i − x_i) (zero where p_i = x_i).
    if (contacts)
      for (int r = 0; r < n; ++r) rhs.row(r) += h2 * contact_weight_ * (target.row(free_[r]) - x.row(free_[r]));
    for (Eigen::Index k = 0; k < m; ++k) {
      const int a = row_[s.springs(k, 0)], b = row_[s.springs(k, 1)];
      const Eigen::RowVector3d kd = h2 * s.stiffness[k] * excess.row(k);
      if (a >= 0) rhs.row(a) -= kd;
      if (b >= 0) rhs.row(b) += kd;
    }
    const Eigen::MatrixXd delta = cholesky_.solve(rhs);
    if (options.chebyshev && it < kChebyshevDelay) {
      previous = x;
      for (int r = 0; r < n; ++r) x.row(free_[r]) += delta.row(r);
    } else if (options.chebyshev) {
      // Wang 2015, eq. 10: ω = 2/(2 − ρ²) at the first accelerated iteration,
      // then ω_{k+1} = 4/(4 − ρ² ω_k); x_{k+1} = ω (x̂_{k+1} − x_{k−1}) + x_{k−1}.
      omega = it == kChebyshevDelay ? 2 / (2 - rho * rho) : 4 / (4 - rho * rho * omega);
      for (int r = 0; r < n; ++r) {
        const int i = free_[r];
        const Eigen::RowVector3d next =
            omega * (x.row(i) + delta.row(r) - previous.row(i)) + previous.row(i);
        previous.row(i) = x.row(i);
        x.row(i) = next;
      }
    } else {
      for (int r = 0; r < n; ++r) x.row(free_[r]) += delta.row(r);
    }
    if (options.project) options.project(x);
    if (options.after_iteration) options.after_iteration();
    ++rep.iterations;
    if (measure) {
      const double g = incremental_gradient(s, x, y, h_).norm() / g0;
      rep.residuals.push_back(g);
      if (g <= options.tolerance) {
        rep.converged = true;
        break;
      }
    }
  }
  return x;
}

}  // namespace loom::cloth
