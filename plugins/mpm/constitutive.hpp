// Constitutive models and plasticity, per particle, in D = 2 or 3.
// Kirchhoff stress τ = P Fᵀ, which MLS-MPM scatters as
// affine = −Δt V⁰ (4/Δx²) τ + m C (Hu et al. 2018, eq. 29 with quadratic B-splines).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "lanes.hpp"
#include "particles.hpp"

namespace loom::mpm {

// Clamps keeping F invertible: singular values and the fluid's J never fall
// below these (counted; the node warns) instead of producing NaN.
constexpr double kMinSingularValue = 0.2;
constexpr double kMinJ = 0.1;

// Snow (Stomakhin et al. 2013): critical compression/stretch θc, θs and hardening ξ,
// the values of the paper and of Taichi's mpm99.
constexpr double kSnowCompression = 2.5e-2, kSnowStretch = 4.5e-3, kSnowHardening = 10.0;
// Sand (Klár et al. 2016): the Drucker–Prager cone's α from the friction angle
// φ_F, α = √(2/3)·2 sin φ_F / (3 − sin φ_F) (eq. 27). Without hardening φ_F is
// fixed; with it (§7.3) it grows with the particle's accumulated plastic
// strain q: φ_F = h0 + (h1 q − h3) e^{−h2 q} (degrees), from h0 − h3 for fresh
// sand towards h0. The defaults are the paper's (h0 = 35°, h1 = 9°, h2 = 0.2,
// h3 = 10°).
struct SandModel {
  double friction_degrees = 30;  // φ_F without hardening
  bool hardening = false;
  double h0 = 35, h1 = 9, h2 = 0.2, h3 = 10;

  double friction_angle(double q) const {  // degrees
    return hardening ? h0 + (h1 * q - h3) * std::exp(-h2 * q) : friction_degrees;
  }
  double alpha(double q) const {
    const double s = std::sin(friction_angle(q) * M_PI / 180.0);
    return std::sqrt(2.0 / 3.0) * 2 * s / (3 - s);
  }
};

// Snow hardening factor h = exp(ξ (1 − Jp)) (Stomakhin 2013, eq. 8), bounded so a
// fully crushed particle cannot stiffen without limit.
inline double snow_hardening(double Jp) {
  return std::exp(std::min(kSnowHardening * (1 - Jp), 10.0));
}

// F = U diag(σ) Vᵀ with U and V rotations (det +1); σ₀ ≥ σ₁ ≥ |σ₂|, the last one
// negative when F is inverted.
template <int D>
struct Svd {
  Eigen::Matrix<double, D, D> U, V;
  Eigen::Matrix<double, D, 1> sigma;
};

// Eigen's Jacobi SVD, reflections moved into the last singular value.
template <int D>
Svd<D> jacobi_svd(const Eigen::Matrix<double, D, D>& F) {
  Eigen::JacobiSVD<Eigen::Matrix<double, D, D>, Eigen::NoQRPreconditioner> svd(
      F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Svd<D> r{svd.matrixU(), svd.matrixV(), svd.singularValues()};
  if (r.U.determinant() < 0) r.U.col(D - 1) *= -1, r.sigma[D - 1] *= -1;
  if (r.V.determinant() < 0) r.V.col(D - 1) *= -1, r.sigma[D - 1] *= -1;
  return r;
}

// 3×3: V from the closed-form eigen-decomposition of FᵀF, U = F V Σ⁻¹
// orthonormalized (Gram–Schmidt, third column a cross product), about 5× faster
// than the Jacobi sweeps. Jacobi where σ₁ is too small for U = F V Σ⁻¹.
template <int D>
Svd<D> svd(const Eigen::Matrix<double, D, D>& F) {
  if constexpr (D == 2) {
    return jacobi_svd<2>(F);
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(F.transpose() * F);
    const Eigen::Vector3d lambda = eig.eigenvalues();  // ascending
    if (!(lambda[1] > 1e-8 * std::max(lambda[2], 1e-300))) return jacobi_svd<3>(F);
    Svd<3> r;
    r.V.col(0) = eig.eigenvectors().col(2);
    r.V.col(1) = eig.eigenvectors().col(1);
    r.V.col(2) = r.V.col(0).cross(r.V.col(1));
    Eigen::Vector3d u0 = F * r.V.col(0), u1 = F * r.V.col(1);
    r.sigma[0] = u0.norm();
    u0 /= r.sigma[0];
    u1 -= u0.dot(u1) * u0;
    r.sigma[1] = u1.norm();
    u1 /= r.sigma[1];
    r.U.col(0) = u0;
    r.U.col(1) = u1;
    r.U.col(2) = u0.cross(u1);
    r.sigma[2] = r.U.col(2).dot(F * r.V.col(2));
    return r;
  }
}

// The SVD of F with its singular values kept at least kMinSingularValue (a
// non-finite one becomes 1); `clamped` says whether any was moved, in which case
// F must be rebuilt from the result.
template <int D>
Svd<D> svd_clamped(const Eigen::Matrix<double, D, D>& F, bool& clamped) {
  Svd<D> f = svd<D>(F);
  clamped = f.sigma.minCoeff() < kMinSingularValue || !std::isfinite(f.sigma.sum());
  if (clamped)
    for (int d = 0; d < D; ++d)
      f.sigma[d] = std::isfinite(f.sigma[d]) ? std::max(f.sigma[d], kMinSingularValue) : 1.0;
  return f;
}

// Whether the SVD's clamp would leave F alone: det F > 0 and every singular value
// at least kMinSingularValue, i.e. FᵀF − σ²I positive definite (Sylvester's
// leading minors). False for a non-finite F too.
template <int D>
bool unclamped(const Eigen::Matrix<double, D, D>& F) {
  constexpr double s2 = kMinSingularValue * kMinSingularValue;
  const Eigen::Matrix<double, D, D> A = F.transpose() * F - s2 * Eigen::Matrix<double, D, D>::Identity();
  const double minor2 = A(0, 0) * A(1, 1) - A(0, 1) * A(0, 1);
  return A(0, 0) > 0 && minor2 > 0 && (D == 2 || A.determinant() > 0) && F.determinant() > 0;
}

// One step of Newton's polar iteration X ← ½ X + (½ / det X) cof X (Higham 1986;
// cof X = det X · X⁻ᵀ, its columns the cross products of X's), on one 3×3 matrix
// (T = double) or on two, lane by lane (T = Pair: each lane does the scalar
// step's operations in its order). X[c] is column c. Returns ‖next − X‖²_F.
template <class T>
T polar_step(const T (&X)[3][3], T (&next)[3][3]) {
  T cof[3][3];
  for (int c = 0; c < 3; ++c) {
    const T(&a)[3] = X[(c + 1) % 3];
    const T(&b)[3] = X[(c + 2) % 3];
    cof[c][0] = a[1] * b[2] - a[2] * b[1];
    cof[c][1] = a[2] * b[0] - a[0] * b[2];
    cof[c][2] = a[0] * b[1] - a[1] * b[0];
  }
  const T det = X[0][0] * cof[0][0] + X[0][1] * cof[0][1] + X[0][2] * cof[0][2];
  const T half_inverse = 0.5 / det;
  T moved{};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) {
      next[c][r] = 0.5 * X[c][r] + half_inverse * cof[c][r];
      const T step = next[c][r] - X[c][r];
      moved += step * step;
    }
  return moved;
}

// Newton's iteration stops when a step moves X by under 1e-9 (quadratic: the next
// would move it by ~1e-18), or fails after 40 steps (σ ≈ 1e6 away from 1).
constexpr double kPolarConverged = 1e-18;  // squared
constexpr int kPolarSteps = 40;

// Where F is unclamped, the rotation R of its polar decomposition F = R S (S
// symmetric positive definite), which is the SVD's U Vᵀ; false otherwise, or when
// Newton's iteration does not converge (R untouched), and the caller takes the
// SVD. 2D closed form: R turns by the angle of (F₀₀ + F₁₁, F₁₀ − F₀₁). 3D:
// Newton's iteration from X = F. No trigonometry: in the stress of the
// fixed-corotated materials it replaces the SVD and its atan2 and sincos.
template <int D>
bool rotation_where_unclamped(const Eigen::Matrix<double, D, D>& F, Eigen::Matrix<double, D, D>& R) {
  if (!unclamped<D>(F)) return false;
  if constexpr (D == 2) {
    const double c = F(0, 0) + F(1, 1), s = F(1, 0) - F(0, 1), r = std::sqrt(c * c + s * s);
    R << c / r, -s / r, s / r, c / r;
    return true;
  } else {
    double X[3][3], next[3][3];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) X[c][r] = F(r, c);
    for (int k = 0; k < kPolarSteps; ++k) {
      const double moved = polar_step(X, next);
      std::memcpy(X, next, sizeof X);
      if (moved < kPolarConverged) {
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) R(r, c) = X[c][r];
        return true;
      }
    }
    return false;
  }
}

// rotation_where_unclamped<3> of two matrices at once, lane l of a Pair for F[l]:
// the two chains of dependent steps (a division and some fifty products and sums
// each) overlap. Each lane steps until its own convergence, then holds, so ok[l] and
// R[l] equal bit for bit what rotation_where_unclamped<3> gives F[l] alone.
inline void rotations_where_unclamped(const Eigen::Matrix3d* const (&F)[2], Eigen::Matrix3d* const (&R)[2],
                                      bool (&ok)[2]) {
  for (int l = 0; l < 2; ++l) ok[l] = unclamped<3>(*F[l]);
  Pair X[3][3], next[3][3];
  for (int c = 0; c < 3; ++c)  // a declined lane steps on the identity, which holds at once
    for (int r = 0; r < 3; ++r)
      X[c][r] = Pair{ok[0] ? (*F[0])(r, c) : double(r == c), ok[1] ? (*F[1])(r, c) : double(r == c)};
  PairMask stepping = {ok[0] ? -1 : 0, ok[1] ? -1 : 0};
  for (int k = 0; k < kPolarSteps && (stepping[0] || stepping[1]); ++k) {
    const Pair moved = polar_step(X, next);
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) X[c][r] = stepping ? next[c][r] : X[c][r];
    stepping &= ~(moved < kPolarConverged);
  }
  for (int l = 0; l < 2; ++l) {
    ok[l] = ok[l] && !stepping[l];
    if (ok[l])
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) (*R[l])(r, c) = X[c][r][l];
  }
}

inline bool fixed_corotated(Material m) { return m == Material::elastic || m == Material::snow; }

// Weakly compressible fluid, mpm88: τ = K (J − 1) I (λ holds K).
template <int D>
Eigen::Matrix<double, D, D> fluid_kirchhoff_stress(const Particles<D>& ps, int p) {
  return Eigen::Matrix<double, D, D>::Identity() * (ps.lambda[p] * (ps.J[p] - 1));
}

// Kirchhoff stress of particle p; R its polar rotation where
// rotation_where_unclamped found one (a fixed-corotated material only), else null.
// May rewrite F[p] (and J[p]) when it has to be clamped away from a singular value
// near zero; returns true then.
template <int D>
bool kirchhoff_stress(Particles<D>& ps, int p, const Eigen::Matrix<double, D, D>* R, Eigen::Matrix<double, D, D>& tau) {
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;
  const Material m = ps.material[p];
  if (m == Material::fluid) {
    tau = fluid_kirchhoff_stress(ps, p);
    return false;
  }
  Mat& F = ps.F[p];
  double mu = ps.mu[p], lambda = ps.lambda[p];
  if (m == Material::snow) {
    const double h = snow_hardening(ps.J[p]);
    mu *= h, lambda *= h;
  }
  // Fixed corotated (Stomakhin 2012): τ = 2μ (F − R) Fᵀ + λ (J − 1) J I, R = U Vᵀ.
  const auto corotated = [&](const Mat& rotation, double J) {
    tau = 2 * mu * (F - rotation) * F.transpose() + Mat::Identity() * (lambda * (J - 1) * J);
  };
  if (R) {
    corotated(*R, F.determinant());
    return false;
  }
  bool clamped = false;
  const Svd<D> f = svd_clamped<D>(F, clamped);
  const Mat &U = f.U, &V = f.V;
  const Vec& sigma = f.sigma;
  if (clamped) F = U * sigma.asDiagonal() * V.transpose();
  if (m == Material::sand) {
    // St. Venant–Kirchhoff on Hencky strain ε = log Σ (Klár 2016, eq. 26):
    // τ = U (2μ ε + λ tr(ε) I) Uᵀ.
    const Vec eps = sigma.array().log().matrix();
    const Vec t = 2 * mu * eps + Vec::Constant(lambda * eps.sum());
    tau = U * t.asDiagonal() * U.transpose();
    return clamped;
  }
  corotated(U * V.transpose(), sigma.prod());
  return clamped;
}

template <int D>
bool kirchhoff_stress(Particles<D>& ps, int p, Eigen::Matrix<double, D, D>& tau) {
  Eigen::Matrix<double, D, D> R;
  const bool polar = fixed_corotated(ps.material[p]) && rotation_where_unclamped<D>(ps.F[p], R);
  return kirchhoff_stress<D>(ps, p, polar ? &R : nullptr, tau);
}

// The stresses of 3D particles p and p + 1, equal bit for bit to two calls of
// kirchhoff_stress; two fixed-corotated particles' polar iterations run side by
// side. Returns how many were clamped.
inline int kirchhoff_stresses(Particles<3>& ps, int p, Eigen::Matrix3d (&tau)[2]) {
  if (fixed_corotated(ps.material[p]) && fixed_corotated(ps.material[p + 1])) {
    Eigen::Matrix3d R0, R1;
    bool ok[2];
    rotations_where_unclamped({&ps.F[p], &ps.F[p + 1]}, {&R0, &R1}, ok);
    return kirchhoff_stress<3>(ps, p, ok[0] ? &R0 : nullptr, tau[0]) +
           kirchhoff_stress<3>(ps, p + 1, ok[1] ? &R1 : nullptr, tau[1]);
  }
  return kirchhoff_stress<3>(ps, p, tau[0]) + kirchhoff_stress<3>(ps, p + 1, tau[1]);
}

// Plastic projection of particle p after F was advanced; true when J had to be
// clamped. Sand returns to the cone of its current α, then adds the plastic
// strain it removed, δq = ‖ε_trial − ε‖_F, to q (Klár 2016, §7.3).
template <int D>
bool plastic_projection(Particles<D>& ps, int p, const SandModel& sand = {}) {
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;
  const Material m = ps.material[p];
  if (m == Material::elastic || m == Material::fluid) return false;
  Mat& F = ps.F[p];
  bool clamped = false;
  const Svd<D> f = svd_clamped<D>(F, clamped);
  const Mat &U = f.U, &V = f.V;
  Vec sigma = f.sigma;
  if (m == Material::snow) {
    // Stomakhin 2013 §7: clamp Σ to [1 − θc, 1 + θs]; the plastic part goes to Jp.
    for (int d = 0; d < D; ++d) {
      const double s = std::clamp(sigma[d], 1 - kSnowCompression, 1 + kSnowStretch);
      ps.J[p] *= sigma[d] / s;
      sigma[d] = s;
    }
  } else {
    // Drucker–Prager return mapping in log-strain space (Klár 2016, Algorithm 2).
    const Vec eps = sigma.array().log().matrix();
    const double tr = eps.sum();
    const Vec dev = eps - Vec::Constant(tr / D);
    const double dev_norm = dev.norm();
    const double mu = ps.mu[p], lambda = ps.lambda[p];
    const double dgamma = dev_norm + (D * lambda + 2 * mu) / (2 * mu) * tr * sand.alpha(ps.q[p]);
    if (dgamma <= 0) {
      // inside the cone: elastic, unchanged
    } else if (tr > 0 || dev_norm == 0) {
      sigma.setOnes();  // expansion: the tip of the cone, stress free
      ps.q[p] += eps.norm();
    } else {
      sigma = (eps - dgamma / dev_norm * dev).array().exp().matrix();
      ps.q[p] += dgamma;  // ‖ε_trial − ε‖ = δγ ‖dev ε‖ / ‖dev ε‖
    }
  }
  F = U * sigma.asDiagonal() * V.transpose();
  return clamped;
}

}  // namespace loom::mpm
