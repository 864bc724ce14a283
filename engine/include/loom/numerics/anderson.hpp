// Plugin author API. Anderson acceleration of a fixed-point iteration
// u ↦ G(u) (Anderson 1965; for local/global solvers Peng, Deng, Zhang, Liu,
// Pan, Zhang 2018, "Anderson Acceleration for Geometry Optimization and
// Physics Simulation", eq. 4): from the last m residuals f_j = G(u_j) − u_j,
// the next iterate is G(u_k) − Σ_j θ_j ΔG_j with θ the least-squares fit of
// f_k by the residual differences ΔF_j = f_{j+1} − f_j (ΔG_j likewise).
//
// The safeguard (Peng et al. §3.2) is the caller's, since only it knows the
// energy: when the extrapolated iterate does not lower the energy below the
// last accepted iterate's, take the plain G(u_k), which does, and reset().
// ARAP (plugins/arap) and cloth's local/global (plugins/cloth) share this.
//
//   u, g  the current iterate and G(u), any shape, flattened to `size`
//         entries (column-major); the result has the same shape.
#pragma once

#include <algorithm>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace loom::numerics {

class AndersonMixing {
 public:
  // m: how many past differences to keep (the window); m = 0 returns G(u)
  // unchanged, the plain iteration.
  AndersonMixing(int m, Eigen::Index size) : m_(std::max(m, 0)), dF_(size, m_), dG_(size, m_) {}
  // Whether the last extrapolate() used a history (false: it returned G(u)).
  bool active() const { return used_ > 0; }
  void reset() { used_ = 0, next_slot_ = 0, have_last_ = false; }

  template <class Matrix>
  Matrix extrapolate(const Matrix& u, const Matrix& g) {
    if (m_ == 0) return g;
    const Eigen::Map<const Eigen::VectorXd> gv(g.data(), g.size());
    const Eigen::VectorXd f = gv - Eigen::Map<const Eigen::VectorXd>(u.data(), u.size());
    if (have_last_) {
      dF_.col(next_slot_) = f - last_f_;
      dG_.col(next_slot_) = gv - last_g_;
      next_slot_ = (next_slot_ + 1) % m_;
      used_ = std::min(used_ + 1, m_);
    }
    last_f_ = f, last_g_ = gv, have_last_ = true;
    if (used_ == 0) return g;
    // θ = argmin ‖f − ΔF θ‖ by the normal equations (m is a few), ridge-
    // regularized a little so nearly parallel differences stay solvable.
    const auto dF = dF_.leftCols(used_);
    Eigen::MatrixXd gram = dF.transpose() * dF;
    gram.diagonal().array() += 1e-10 * gram.diagonal().maxCoeff() + 1e-300;
    const Eigen::VectorXd theta = gram.ldlt().solve(dF.transpose() * f);
    if (!theta.allFinite()) {
      reset();
      return g;
    }
    Matrix next = g;
    Eigen::Map<Eigen::VectorXd>(next.data(), next.size()) -= dG_.leftCols(used_) * theta;
    return next;
  }

 private:
  int m_, used_ = 0, next_slot_ = 0;
  bool have_last_ = false;
  Eigen::MatrixXd dF_, dG_;
  Eigen::VectorXd last_f_, last_g_;
};

}  // namespace loom::numerics
