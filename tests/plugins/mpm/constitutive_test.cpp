// The 3×3 SVD used by the constitutive models, and the stresses, against
// independent references.
#include "constitutive.hpp"

#include <random>

#include <gtest/gtest.h>

namespace loom::mpm {
namespace {

void expect_valid(const Eigen::Matrix3d& F, const Svd<3>& r, double tol) {
  EXPECT_LT((r.U * r.sigma.asDiagonal() * r.V.transpose() - F).norm(), tol * std::max(1.0, F.norm()));
  EXPECT_LT((r.U.transpose() * r.U - Eigen::Matrix3d::Identity()).norm(), tol);
  EXPECT_LT((r.V.transpose() * r.V - Eigen::Matrix3d::Identity()).norm(), tol);
  EXPECT_NEAR(r.U.determinant(), 1, tol);
  EXPECT_NEAR(r.V.determinant(), 1, tol);
  // Singular values agree with Eigen's Jacobi SVD (up to the sign of the last).
  Eigen::JacobiSVD<Eigen::Matrix3d> ref(F);
  Eigen::Vector3d s = r.sigma;
  s[2] = std::abs(s[2]);
  EXPECT_LT((s - ref.singularValues()).norm(), tol * std::max(1.0, F.norm()));
}

TEST(Constitutive, FastSvdMatchesJacobi) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  for (int k = 0; k < 2000; ++k) {
    Eigen::Matrix3d F;
    for (int i = 0; i < 9; ++i) F(i / 3, i % 3) = n(rng);
    const double scale = k % 3 == 0 ? 1e-3 : (k % 3 == 1 ? 0.1 : 1.0);
    F = Eigen::Matrix3d::Identity() + scale * F;  // near the identity, as in MPM, and beyond
    expect_valid(F, svd<3>(F), 1e-9);
  }
  // Exactly repeated singular values, a reflection, a rank-deficient matrix.
  expect_valid(Eigen::Matrix3d::Identity(), svd<3>(Eigen::Matrix3d::Identity()), 1e-12);
  expect_valid(Eigen::Vector3d(1, 1, -1).asDiagonal().toDenseMatrix(),
               svd<3>(Eigen::Vector3d(1, 1, -1).asDiagonal().toDenseMatrix()), 1e-12);
  Eigen::Matrix3d flat = Eigen::Matrix3d::Zero();
  flat(0, 0) = 2;
  expect_valid(flat, svd<3>(flat), 1e-12);
}

TEST(Constitutive, FixedCorotatedStressOfARotatedStretch) {
  // F = R S with R a rotation and S = diag(s): τ = 2μ (F − R) Fᵀ + λ (J − 1) J I.
  Particles<3> ps;
  ps.add(Eigen::Vector3d::Constant(0.5), Eigen::Vector3d::Zero(), Material::elastic, {2.0, 3.0}, 1, 1,
         Eigen::Vector3f::Ones());
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d s(1.1, 0.95, 0.9);
  ps.F[0] = R * s.asDiagonal();
  const double J = s.prod();
  const Eigen::Matrix3d expected =
      R * (2 * 2.0 * (s.array() - 1) * s.array()).matrix().asDiagonal() * R.transpose() +
      Eigen::Matrix3d::Identity() * 3.0 * (J - 1) * J;
  Eigen::Matrix3d tau;
  kirchhoff_stress(ps, 0, tau);
  EXPECT_LT((tau - expected).norm(), 1e-12);
}

TEST(Constitutive, SnowAndSandProjections) {
  Particles<3> ps;
  const Lame lame = lame_parameters(Material::sand, 1e4, 0.3);
  ps.add(Eigen::Vector3d::Constant(0.5), Eigen::Vector3d::Zero(), Material::snow, lame, 1, 1,
         Eigen::Vector3f::Ones());
  ps.add(Eigen::Vector3d::Constant(0.5), Eigen::Vector3d::Zero(), Material::sand, lame, 1, 1,
         Eigen::Vector3f::Ones());
  // Snow stretched 10% along x: clamped to 1 + θs, the rest moves into Jp.
  ps.F[0] = Eigen::Vector3d(1.1, 1, 1).asDiagonal();
  plastic_projection(ps, 0);
  EXPECT_NEAR(ps.F[0](0, 0), 1 + kSnowStretch, 1e-12);
  EXPECT_NEAR(ps.J[0], 1.1 / (1 + kSnowStretch), 1e-12);
  // Sand under expansion goes to the tip of the cone (stress free, F = I up to rotation).
  ps.F[1] = Eigen::Vector3d(1.05, 1.02, 1.01).asDiagonal();
  plastic_projection(ps, 1);
  EXPECT_LT((ps.F[1] - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  // Pure compression (no deviatoric part beyond the cone) stays elastic.
  ps.F[1] = Eigen::Vector3d(0.99, 0.99, 0.99).asDiagonal();
  plastic_projection(ps, 1);
  EXPECT_LT((ps.F[1] - Eigen::Vector3d(0.99, 0.99, 0.99).asDiagonal().toDenseMatrix()).norm(), 1e-12);
}

}  // namespace
}  // namespace loom::mpm
