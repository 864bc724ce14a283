#include <cmath>
#include <utility>

#include <Eigen/SparseCore>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "implicit_solvers.hpp"
#include "incremental_potential.hpp"
#include "loom/numerics/anderson.hpp"

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

double LocalGlobalSolver::local_step(const SpringSystem& s, const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y,
                                     const SolveOptions& options, bool energy, Eigen::MatrixX3d& excess,
                                     Eigen::MatrixX3d& target) const {
  const Eigen::Index m = s.springs.rows();
  excess.resize(m, 3);
  // r_s − d_s with d_s = l_s r_s/‖r_s‖ the rest-length vector along each spring.
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, m, 4096), [&](const auto& range) {
    for (Eigen::Index k = range.begin(); k != range.end(); ++k) {
      const Eigen::RowVector3d r = x.row(s.springs(k, 0)) - x.row(s.springs(k, 1));
      const double len = r.norm();
      // Coincident ends: d_s = 0 (the nearest point of the rest sphere is
      // undefined there, and any choice leaves E unchanged).
      excess.row(k) = len > 0 ? Eigen::RowVector3d((1 - s.rest_length[k] / len) * r) : r;
    }
  });
  const bool contacts = contact_weight_ > 0 && options.contact_target;
  if (contacts) options.contact_target(x, target);
  if (!energy) return 0;
  // Serial sums, so E does not depend on the thread count.
  double inertia = 0, elastic = 0;
  for (const int i : free_) {
    inertia += s.mass[i] * (x.row(i) - y.row(i)).squaredNorm();
    if (contacts) elastic += contact_weight_ * (x.row(i) - target.row(i)).squaredNorm();
  }
  for (Eigen::Index k = 0; k < m; ++k) elastic += s.stiffness[k] * excess.row(k).squaredNorm();
  return 0.5 * inertia + 0.5 * h_ * h_ * elastic;
}

double LocalGlobalSolver::energy_change(const SpringSystem& s, const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b,
                                        const Eigen::MatrixX3d& y, const Eigen::MatrixX3d* target_a,
                                        const Eigen::MatrixX3d* target_b) const {
  // Each term's change as a difference of squares, ‖u'‖² − ‖u‖² = (u' − u)·(u' + u)
  // with u' − u formed from b − a: its rounding error is relative to the
  // change, not to E (near the minimizer of a stiff cloth E's relative
  // changes fall below 1e-16 while ‖∇E‖ is still 1e-5 of its start).
  const Eigen::Index m = s.springs.rows();
  Eigen::VectorXd spring(m);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, m, 4096), [&](const auto& range) {
    for (Eigen::Index k = range.begin(); k != range.end(); ++k) {
      const int i = s.springs(k, 0), j = s.springs(k, 1);
      const Eigen::RowVector3d ra = a.row(i) - a.row(j), rb = b.row(i) - b.row(j);
      const Eigen::RowVector3d dr = (b.row(i) - a.row(i)) - (b.row(j) - a.row(j));
      const double la = ra.norm(), lb = rb.norm();
      // ‖r_b‖ − ‖r_a‖ = (r_b − r_a)·(r_b + r_a) / (‖r_b‖ + ‖r_a‖); (l_b − l)² − (l_a − l)² = Δl (l_b + l_a − 2l).
      const double dl = la + lb > 0 ? dr.dot(rb + ra) / (la + lb) : 0;
      spring[k] = s.stiffness[k] * dl * (la + lb - 2 * s.rest_length[k]);
    }
  });
  double inertia = 0, elastic = spring.sum();  // serial sums: independent of the thread count
  for (const int i : free_) {
    const Eigen::RowVector3d d = b.row(i) - a.row(i);
    inertia += s.mass[i] * d.dot(b.row(i) + a.row(i) - 2 * y.row(i));
    if (target_a) {
      const Eigen::RowVector3d ca = a.row(i) - target_a->row(i), cb = b.row(i) - target_b->row(i);
      elastic += contact_weight_ * (d - (target_b->row(i) - target_a->row(i))).dot(cb + ca);
    }
  }
  return 0.5 * inertia + 0.5 * h_ * h_ * elastic;
}

Eigen::MatrixXd LocalGlobalSolver::global_step(const SpringSystem& s, const Eigen::MatrixX3d& x,
                                               const Eigen::MatrixX3d& y, const Eigen::MatrixX3d& excess,
                                               const Eigen::MatrixX3d* target) const {
  // (M + h² L) x = M y + h² J d, solved for the change Δ = x_{k+1} − x_k:
  // (M + h² L) Δ = M (y − x_k) − h² Σ_s k_s A_s (r_s − d_s)ᵀ. The right-hand
  // side is small near convergence and computed without cancellation, so Δ
  // keeps full relative accuracy however large x is (fixed neighbours enter
  // through r_s).
  const double h2 = h_ * h_;
  const int n = static_cast<int>(free_.size());
  Eigen::MatrixX3d rhs(n, 3);
  for (int r = 0; r < n; ++r) rhs.row(r) = s.mass[free_[r]] * (y.row(free_[r]) - x.row(free_[r]));
  // Contact constraints: + h² w (p_i − x_i) (zero where p_i = x_i).
  if (target)
    for (int r = 0; r < n; ++r) rhs.row(r) += h2 * contact_weight_ * (target->row(free_[r]) - x.row(free_[r]));
  for (Eigen::Index k = 0; k < s.springs.rows(); ++k) {
    const int a = row_[s.springs(k, 0)], b = row_[s.springs(k, 1)];
    const Eigen::RowVector3d kd = h2 * s.stiffness[k] * excess.row(k);
    if (a >= 0) rhs.row(a) -= kd;
    if (b >= 0) rhs.row(b) += kd;
  }
  return cholesky_.solve(rhs);
}

// Liu et al. (2013)'s iteration and its two accelerations as one loop, with
// the convergence measure beside them.
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
  const bool measure = options.record_residuals || options.tolerance > 0;
  const double g0 = measure ? incremental_gradient(s, x, y, h_).norm() : 1;
  if (measure) rep.start_gradient = g0;
  if (measure && g0 == 0) {
    rep.converged = true;
    return x;
  }
  const bool contacts = contact_weight_ > 0 && options.contact_target;
  const bool anderson = options.anderson > 0 && !options.chebyshev;
  Eigen::MatrixX3d excess, target;  // the local step at x: r_s − d_s, contact projections p_i
  Eigen::MatrixX3d previous = x;    // x_{k−1} for Chebyshev
  double omega = 1;
  const double rho = options.chebyshev_rho;
  numerics::AndersonMixing mixing(anderson ? options.anderson : 0, x.size());
  // E of the accepted iterate x (Anderson only: the start's, then summed
  // changes), whose local step is in `excess`, `target`.
  double E = local_step(s, x, y, options, anderson, excess, target);
  if (anderson) rep.energies.push_back(E);
  Eigen::MatrixX3d next_target;
  bool local_done = true;  // whether `excess` and `target` are x's
  for (int it = 0; it < options.iterations; ++it) {
    if (!local_done) local_step(s, x, y, options, false, excess, target);
    const Eigen::MatrixXd delta = global_step(s, x, y, excess, contacts ? &target : nullptr);
    Eigen::MatrixX3d plain = x;  // G(x_k), the plain iterate
    for (int r = 0; r < n; ++r) plain.row(free_[r]) += delta.row(r);
    if (anderson) {
      Eigen::MatrixX3d next = mixing.extrapolate(x, plain);
      auto evaluate = [&] {  // the local step at `next`, and E(next) − E(x)
        if (options.project) options.project(next);
        local_step(s, next, y, options, false, excess, next_target);
        return energy_change(s, x, next, y, contacts ? &target : nullptr, contacts ? &next_target : nullptr);
      };
      double change = evaluate();
      if (!(change < 0) && mixing.active()) {
        // Safeguard (Peng et al. 2018, §3.2): the extrapolation did not lower
        // E; the plain step does (Liu et al.'s guarantee), and the history
        // starts again.
        ++rep.rejected;
        mixing.reset();
        next = std::move(plain);
        change = evaluate();
      }
      x = std::move(next);
      std::swap(target, next_target);
      E += change;
      rep.energies.push_back(E);
    } else {
      if (options.chebyshev && it >= kChebyshevDelay) {
        // Wang 2015, eq. 10: ω = 2/(2 − ρ²) at the first accelerated iteration,
        // then ω_{k+1} = 4/(4 − ρ² ω_k); x_{k+1} = ω (x̂_{k+1} − x_{k−1}) + x_{k−1}.
        omega = it == kChebyshevDelay ? 2 / (2 - rho * rho) : 4 / (4 - rho * rho * omega);
        for (const int i : free_) plain.row(i) = omega * (plain.row(i) - previous.row(i)) + previous.row(i);
      }
      previous = std::move(x);
      x = std::move(plain);
      if (options.project) options.project(x);
      local_done = false;
    }
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
