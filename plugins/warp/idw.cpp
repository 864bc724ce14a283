#include "idw.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "vector_clones.hpp"

namespace loom::warp {

namespace {

// σ is evaluated at d² + 1e-18 (a billionth of a pixel): finite on a source,
// where the pixel then gets q_i exactly (see evaluate_idw_row), and no branch
// in the loop, which then vectorizes.
constexpr double kHit2 = 1e-18;

double idw_sigma(double d2, double mu) {
  d2 += kHit2;
  return mu == 2 ? 1 / d2 : std::exp(-0.5 * mu * std::log(d2));
}

// The per-center accumulation over a row: σ for μ = 2 and μ = 1 is a
// division and a sqrt, which vectorize (kMu = 0: any μ, by exp/log).
template <int kMu>
inline __attribute__((always_inline)) void accumulate(const IdwMap& m, double y, const double* x, int n,
                                                      double* sw, double* sx, double* sy) {
  const double half_mu = 0.5 * m.mu;
  for (Eigen::Index k = 0; k < m.p.rows(); ++k) {
    const double px = m.p(k, 0), py = m.p(k, 1), qx = m.q(k, 0), qy = m.q(k, 1);
    const double uy = y - py, dy2 = uy * uy;
    const Eigen::Matrix2d& D = m.D[static_cast<std::size_t>(k)];
    const double d00 = D(0, 0), d01 = D(0, 1), d10 = D(1, 0), d11 = D(1, 1);
    const double cx = qx + d01 * uy, cy = qy + d11 * uy;
    for (int j = 0; j < n; ++j) {
      const double ux = x[j] - px;
      const double d2 = ux * ux + dy2 + kHit2;
      double s;
      if constexpr (kMu == 2) s = 1 / d2;
      else if constexpr (kMu == 1) s = 1 / std::sqrt(d2);
      else s = std::exp(-half_mu * std::log(d2));
      sw[j] += s;
      sx[j] += s * (cx + d00 * ux);
      sy[j] += s * (cy + d10 * ux);
    }
  }
}

LOOM_WARP_VECTOR_CLONES
void accumulate_power2(const IdwMap& m, double y, const double* x, int n, double* sw, double* sx, double* sy) {
  accumulate<2>(m, y, x, n, sw, sx, sy);
}

LOOM_WARP_VECTOR_CLONES
void accumulate_power1(const IdwMap& m, double y, const double* x, int n, double* sw, double* sx, double* sy) {
  accumulate<1>(m, y, x, n, sw, sx, sy);
}

}  // namespace

IdwMap fit_idw(const Eigen::MatrixX2d& P, const Eigen::MatrixX2d& Q, double mu, bool fit_affine) {
  IdwMap m{P, Q, std::vector<Eigen::Matrix2d>(static_cast<std::size_t>(P.rows()), Eigen::Matrix2d::Zero()), mu};
  if (!fit_affine) return m;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero(), B = Eigen::Matrix2d::Zero();
    for (Eigen::Index j = 0; j < P.rows(); ++j) {
      if (j == i) continue;
      const Eigen::Vector2d dp = (P.row(j) - P.row(i)).transpose();
      const Eigen::Vector2d dq = (Q.row(j) - Q.row(i)).transpose();
      const double s = idw_sigma(dp.squaredNorm(), mu);
      A += s * dp * dp.transpose();
      B += s * dq * dp.transpose();
    }
    // Scaled by trace(A) so that the 2×2 inverse stays in range for any μ.
    const double t = A.trace();
    if (!(t > 0) || !std::isfinite(t)) {
      m.D[static_cast<std::size_t>(i)].setIdentity();
      continue;
    }
    const Eigen::Matrix2d eps = 1e-9 * Eigen::Matrix2d::Identity();
    m.D[static_cast<std::size_t>(i)] = (B / t + eps) * (A / t + eps).inverse();
  }
  return m;
}

void evaluate_idw_row(const IdwMap& m, double y, const double* x, int n, double* fx, double* fy) {
  if (m.p.rows() == 0) {
    std::copy(x, x + n, fx);
    std::fill(fy, fy + n, y);
    return;
  }
  std::vector<double> sw(static_cast<std::size_t>(n), 0.0);
  std::fill(fx, fx + n, 0.0);
  std::fill(fy, fy + n, 0.0);
  const double mu = m.mu;
  if (mu == 2)
    accumulate_power2(m, y, x, n, sw.data(), fx, fy);
  else if (mu == 1)
    accumulate_power1(m, y, x, n, sw.data(), fx, fy);
  else
    accumulate<0>(m, y, x, n, sw.data(), fx, fy);
  const double hit_sigma = idw_sigma(0, mu);
  for (int j = 0; j < n; ++j) {
    if (sw[j] >= hit_sigma) {  // on a source: f = q_i exactly, not a 1e-18-weighted mean
      Eigen::Index best = 0;
      double best_d2 = INFINITY;
      for (Eigen::Index k = 0; k < m.p.rows(); ++k) {
        const double d2 = (Eigen::Vector2d(x[j], y) - m.p.row(k).transpose()).squaredNorm();
        if (d2 < best_d2) best_d2 = d2, best = k;
      }
      if (best_d2 <= kHit2) {
        fx[j] = m.q(best, 0);
        fy[j] = m.q(best, 1);
        continue;
      }
    }
    fx[j] /= sw[j];
    fy[j] /= sw[j];
  }
}

Eigen::MatrixX2d evaluate_idw(const IdwMap& m, const Eigen::MatrixX2d& X) {
  Eigen::MatrixX2d F(X.rows(), 2);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    double fx, fy;
    evaluate_idw_row(m, X(i, 1), &X(i, 0), 1, &fx, &fy);
    F(i, 0) = fx;
    F(i, 1) = fy;
  }
  return F;
}

}  // namespace loom::warp
