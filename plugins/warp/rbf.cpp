#include "rbf.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "vector_clones.hpp"

namespace loom::warp {

namespace {

double kernel_value(const RbfMap& m, double d2, double r2) {
  if (m.kernel == RbfKernel::thin_plate) return d2 > 0 ? 0.5 * d2 * std::log(d2) : 0.0;
  const double t = d2 + r2;
  if (m.mu == 1) return std::sqrt(t);
  return std::exp(0.5 * m.mu * std::log(t));
}

// Adds Σ_k a_k g(‖x − p_k‖) along a row, one center at a time so that the
// inner loop runs over pixels and vectorizes (no reduction to reorder).
template <class G>
void accumulate(const RbfMap& m, double y, const double* x, int n, double* fx, double* fy, G g) {
  for (Eigen::Index k = 0; k < m.p.rows(); ++k) {
    const double px = m.p(k, 0), dy = y - m.p(k, 1), c = dy * dy + m.r2[k];
    const double ax = m.a(k, 0), ay = m.a(k, 1);
    for (int j = 0; j < n; ++j) {
      const double dx = x[j] - px;
      const double v = g(dx * dx + c);
      fx[j] += ax * v;
      fy[j] += ay * v;
    }
  }
}

// The same for μ = 1 and μ = −1, as plain functions so that their AVX2 clones
// get the sqrt inlined and vectorized.
LOOM_WARP_VECTOR_CLONES
void accumulate_multiquadric(const RbfMap& m, double y, const double* x, int n, double* fx, double* fy) {
  for (Eigen::Index k = 0; k < m.p.rows(); ++k) {
    const double px = m.p(k, 0), dy = y - m.p(k, 1), c = dy * dy + m.r2[k];
    const double ax = m.a(k, 0), ay = m.a(k, 1);
    for (int j = 0; j < n; ++j) {
      const double dx = x[j] - px;
      const double v = std::sqrt(dx * dx + c);
      fx[j] += ax * v;
      fy[j] += ay * v;
    }
  }
}

LOOM_WARP_VECTOR_CLONES
void accumulate_inverse_multiquadric(const RbfMap& m, double y, const double* x, int n, double* fx, double* fy) {
  for (Eigen::Index k = 0; k < m.p.rows(); ++k) {
    const double px = m.p(k, 0), dy = y - m.p(k, 1), c = dy * dy + m.r2[k];
    const double ax = m.a(k, 0), ay = m.a(k, 1);
    for (int j = 0; j < n; ++j) {
      const double dx = x[j] - px;
      const double v = 1 / std::sqrt(dx * dx + c);
      fx[j] += ax * v;
      fy[j] += ay * v;
    }
  }
}

// Solves M X = R; a singular M gets the minimum-norm least-squares solution.
Eigen::MatrixXd solve_or_least_squares(const Eigen::MatrixXd& M, const Eigen::MatrixXd& R,
                                       std::vector<std::string>* notes, const char* what) {
  Eigen::MatrixXd X = M.partialPivLu().solve(R);
  // Accepted when it reproduces R to 1e-9 of its size; a singular M leaves a
  // residual of the size of R (or NaN) instead.
  if (X.allFinite() && (M * X - R).cwiseAbs().maxCoeff() <= 1e-9 * R.cwiseAbs().maxCoeff() + 1e-300)
    return X;
  if (notes)
    notes->push_back(std::string(what) +
                     " is singular: used the least-squares solution (raise lambda, or change mu)");
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(M);
  cod.setThreshold(1e-12);
  X = cod.solve(R);
  if (!X.allFinite()) X.setZero();
  return X;
}

}  // namespace

void fit_affine_part(const Eigen::MatrixX2d& P, const Eigen::MatrixX2d& Q, Eigen::Matrix2d& A,
                     Eigen::Vector2d& b) {
  const Eigen::Index n = P.rows();
  A.setIdentity();
  b.setZero();
  if (n == 0) return;
  const Eigen::RowVector2d pm = P.colwise().mean(), qm = Q.colwise().mean();
  if (n >= 2) {
    const Eigen::MatrixX2d Pc = P.rowwise() - pm, Qc = Q.rowwise() - qm;
    const Eigen::Matrix2d S = Pc.transpose() * Pc;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(S);
    if (n >= 3 && eig.eigenvalues()[0] > 1e-12 * eig.eigenvalues()[1]) {
      A = S.ldlt().solve(Pc.transpose() * Qc).transpose();
    } else {
      // Two points, or points on a line: its two extreme points set the scale.
      const Eigen::VectorXd t = Pc * eig.eigenvectors().col(1);
      Eigen::Index lo, hi;
      t.minCoeff(&lo);
      t.maxCoeff(&hi);
      const double dp = (P.row(hi) - P.row(lo)).norm();
      if (dp > 0) A *= (Q.row(hi) - Q.row(lo)).norm() / dp;
    }
  }
  b = qm.transpose() - A * pm.transpose();
}

RbfMap fit_rbf(const Eigen::MatrixX2d& P, const Eigen::MatrixX2d& Q, RbfKernel kernel, double mu,
               double lambda, std::vector<std::string>* notes) {
  const Eigen::Index n = P.rows();
  RbfMap m;
  m.kernel = kernel;
  m.mu = mu;
  m.p = P;
  m.a = Eigen::MatrixX2d::Zero(n, 2);
  m.r2 = Eigen::VectorXd::Ones(n);
  if (kernel == RbfKernel::multiquadric && n >= 2) {
    for (Eigen::Index i = 0; i < n; ++i) {
      double best = INFINITY;
      for (Eigen::Index j = 0; j < n; ++j)
        if (j != i) best = std::min(best, (P.row(j) - P.row(i)).squaredNorm());
      m.r2[i] = best;
    }
  }
  if (kernel == RbfKernel::thin_plate) m.r2.setZero();
  Eigen::MatrixXd G(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      G(i, j) = kernel_value(m, (P.row(i) - P.row(j)).squaredNorm(), m.r2[j]);
  G.diagonal().array() += lambda;

  if (kernel == RbfKernel::thin_plate && n >= 3) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + 3, n + 3), R = Eigen::MatrixXd::Zero(n + 3, 2);
    M.topLeftCorner(n, n) = G;
    M.block(0, n, n, 1).setOnes();
    M.block(0, n + 1, n, 2) = P;
    M.bottomLeftCorner(3, n) = M.topRightCorner(n, 3).transpose();
    R.topRows(n) = Q;
    const Eigen::MatrixXd X = solve_or_least_squares(M, R, notes, "the thin-plate system");
    m.a = X.topRows(n);
    m.b = X.row(n).transpose();
    m.A = X.bottomRows(2).transpose();
    return m;
  }
  fit_affine_part(P, Q, m.A, m.b);
  if (n == 0) return m;
  const Eigen::MatrixX2d residual = Q - ((P * m.A.transpose()).rowwise() + m.b.transpose());
  m.a = solve_or_least_squares(G, residual, notes, "the RBF kernel matrix");
  return m;
}

void evaluate_rbf_row(const RbfMap& m, double y, const double* x, int n, double* fx, double* fy) {
  const double a00 = m.A(0, 0), a01 = m.A(0, 1), a10 = m.A(1, 0), a11 = m.A(1, 1);
  const double bx = m.b[0] + a01 * y, by = m.b[1] + a11 * y;
  for (int j = 0; j < n; ++j) {
    fx[j] = a00 * x[j] + bx;
    fy[j] = a10 * x[j] + by;
  }
  if (m.kernel == RbfKernel::thin_plate)
    accumulate(m, y, x, n, fx, fy, [](double d2) { return d2 > 0 ? 0.5 * d2 * std::log(d2) : 0.0; });
  else if (m.mu == 1)
    accumulate_multiquadric(m, y, x, n, fx, fy);
  else if (m.mu == -1)
    accumulate_inverse_multiquadric(m, y, x, n, fx, fy);
  else {
    const double half_mu = 0.5 * m.mu;
    accumulate(m, y, x, n, fx, fy, [half_mu](double t) { return std::exp(half_mu * std::log(t)); });
  }
}

Eigen::MatrixX2d evaluate_rbf(const RbfMap& m, const Eigen::MatrixX2d& X) {
  Eigen::MatrixX2d F(X.rows(), 2);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    double fx, fy;
    evaluate_rbf_row(m, X(i, 1), &X(i, 0), 1, &fx, &fy);
    F(i, 0) = fx;
    F(i, 1) = fy;
  }
  return F;
}

}  // namespace loom::warp
