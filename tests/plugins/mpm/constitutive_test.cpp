// The 3×3 SVD used by the constitutive models, and the stresses, against
// independent references.
#include "constitutive.hpp"

#include <cstdio>
#include <cstring>
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

// The polar rotation that replaces the SVD in the fixed-corotated stress: on
// F = U diag(σ) Vᵀ built from random rotations it equals U Vᵀ (the reference is
// the construction, not a decomposition), and it declines, leaving the SVD's
// clamp to act, exactly where that clamp would: a σ below kMinSingularValue, an
// inverted F, a non-finite one.
template <int D>
void check_polar_rotation(std::uint64_t seed) {
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), log_sigma(std::log(0.21), std::log(50.0));
  const auto rotation = [&] {
    if constexpr (D == 2)
      return Mat(Eigen::Rotation2Dd(angle(rng)).toRotationMatrix());
    else
      return Mat(Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::Random().normalized()).toRotationMatrix());
  };
  double worst_polar = 0, worst_svd = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Mat U = rotation(), V = rotation();
    Vec sigma;
    for (int d = 0; d < D; ++d)
      sigma[d] = trial % 2 ? 1 + 0.1 * (std::exp(log_sigma(rng)) - 1) / 50 : std::exp(log_sigma(rng));
    const Mat F = U * sigma.asDiagonal() * V.transpose();
    Mat R;
    ASSERT_TRUE(rotation_where_unclamped<D>(F, R)) << "trial " << trial << ", σ " << sigma.transpose();
    EXPECT_LT((R - U * V.transpose()).norm(), 1e-12) << "trial " << trial;
    EXPECT_LT((R.transpose() * R - Mat::Identity()).norm(), 1e-14) << "trial " << trial;
    // The SVD path would not have clamped either; it gives U Vᵀ less exactly where
    // σ spreads (FᵀF squares the condition number): within 1e-12 near the identity.
    bool clamped = true;
    const Svd<D> f = svd_clamped<D>(F, clamped);
    EXPECT_FALSE(clamped);
    const double svd_error = (f.U * f.V.transpose() - U * V.transpose()).norm();
    if (trial % 2) {
      EXPECT_LT(svd_error, 1e-12) << "trial " << trial;
    }
    worst_polar = std::max(worst_polar, (R - U * V.transpose()).norm());
    worst_svd = std::max(worst_svd, svd_error);
  }
  std::printf("U Vᵀ to within %.1e by the polar iteration, %.1e by the SVD\n", worst_polar, worst_svd);
  Mat R = Mat::Zero();
  Vec low = Vec::Ones(), inverted = Vec::Ones();
  low[D - 1] = 0.99 * kMinSingularValue;
  inverted[D - 1] = -1;
  EXPECT_FALSE(rotation_where_unclamped<D>(Mat(low.asDiagonal()), R));
  low[D - 1] = 1.01 * kMinSingularValue;
  EXPECT_TRUE(rotation_where_unclamped<D>(Mat(low.asDiagonal()), R));
  R.setZero();
  EXPECT_FALSE(rotation_where_unclamped<D>(Mat(inverted.asDiagonal()), R));
  EXPECT_FALSE(rotation_where_unclamped<D>(Mat::Constant(std::nan("")), R));
  EXPECT_EQ(R, Mat::Zero());  // untouched where it declines
}

TEST(Constitutive, PolarRotationIsTheSvdsWhereNothingIsClamped2D) { check_polar_rotation<2>(21); }
TEST(Constitutive, PolarRotationIsTheSvdsWhereNothingIsClamped3D) { check_polar_rotation<3>(22); }

// Two particles' polar iterations side by side give each exactly what it gets
// alone (bit for bit), when the lanes need different numbers of steps and when
// one or both decline (a low σ, an inverted F, NaN), so the stress pass's
// results do not depend on how particles are paired.
TEST(Constitutive, PairedPolarRotationsEqualOneAtATimeBitForBit) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), log_sigma(std::log(0.21), std::log(50.0));
  const auto random_F = [&](int kind) {
    const auto rotation = [&] {
      return Eigen::Matrix3d(Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::Random().normalized()));
    };
    Eigen::Vector3d sigma;
    for (int d = 0; d < 3; ++d) sigma[d] = kind == 0 ? 1 + 0.01 * angle(rng) : std::exp(log_sigma(rng));
    if (kind == 2) sigma[2] = 0.5 * kMinSingularValue;
    if (kind == 3) sigma[1] = -sigma[1];
    Eigen::Matrix3d F = rotation() * sigma.asDiagonal() * rotation().transpose();
    if (kind == 4) F(1, 2) = std::nan("");
    return F;
  };
  int steps_differ = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::Matrix3d F0 = random_F(trial % 5), F1 = random_F((trial / 5) % 5);
    Eigen::Matrix3d R0 = Eigen::Matrix3d::Zero(), R1 = R0, alone0 = R0, alone1 = R0;
    bool ok[2];
    rotations_where_unclamped({&F0, &F1}, {&R0, &R1}, ok);
    EXPECT_EQ(ok[0], rotation_where_unclamped<3>(F0, alone0)) << "trial " << trial;
    EXPECT_EQ(ok[1], rotation_where_unclamped<3>(F1, alone1)) << "trial " << trial;
    EXPECT_EQ(std::memcmp(R0.data(), alone0.data(), sizeof R0), 0) << "trial " << trial;
    EXPECT_EQ(std::memcmp(R1.data(), alone1.data(), sizeof R1), 0) << "trial " << trial;
    steps_differ += trial % 5 == 0 && (trial / 5) % 5 == 1;
  }
  EXPECT_GT(steps_differ, 10);  // a near-identity lane beside a far one
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

TEST(Constitutive, SandHardeningCurveIsThePapers) {
  // Klár 2016 §7.3 with its defaults: fresh sand at h0 − h3 = 25°, the angle
  // rising to a peak, then back to h0 = 35° as q grows.
  SandModel sand;
  sand.hardening = true;
  EXPECT_DOUBLE_EQ(sand.friction_angle(0), 25);
  EXPECT_NEAR(sand.friction_angle(1), 35 + (9 - 10) * std::exp(-0.2), 1e-12);
  EXPECT_NEAR(sand.friction_angle(200), 35, 1e-9);
  EXPECT_GT(sand.friction_angle(0.5), sand.friction_angle(0));
  const double s = std::sin(25 * M_PI / 180);
  EXPECT_NEAR(sand.alpha(0), std::sqrt(2.0 / 3.0) * 2 * s / (3 - s), 1e-15);
  sand.hardening = false;
  EXPECT_DOUBLE_EQ(sand.friction_angle(7), 30);
}

// Drucker–Prager: after the return mapping the Kirchhoff stress lies in the
// cone ‖dev τ‖_F + α tr τ ≤ 0 of the α the particle had (Klár 2016, eq. 25:
// St. Venant–Kirchhoff on Hencky strain, so dev τ = 2μ dev ε and
// tr τ = (Dλ + 2μ) tr ε), checked on random deformations; a state already
// inside is left alone; q grows by the plastic strain removed.
template <int D>
void check_return_mapping(std::uint64_t seed) {
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> stretch(0.75, 1.25), angle(-M_PI, M_PI), hardness(0, 8);
  SandModel sand;
  sand.hardening = true;
  int projected = 0, inside = 0, tip = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Particles<D> ps;
    ps.add(Vec::Constant(0.5), Vec::Zero(), Material::sand, lame_parameters(Material::sand, 1e4, 0.3), 1, 1,
           Eigen::Vector3f::Ones());
    ps.q[0] = hardness(rng);
    const double alpha = sand.alpha(ps.q[0]);
    Mat R1, R2;
    if constexpr (D == 2) {
      R1 = Eigen::Rotation2Dd(angle(rng)).toRotationMatrix();
      R2 = Eigen::Rotation2Dd(angle(rng)).toRotationMatrix();
    } else {
      R1 = Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::Random().normalized()).toRotationMatrix();
      R2 = Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::Random().normalized()).toRotationMatrix();
    }
    Vec sigma;
    for (int d = 0; d < D; ++d) sigma[d] = stretch(rng);
    const Mat F = R1 * sigma.asDiagonal() * R2;
    ps.F[0] = F;
    const double q0 = ps.q[0];
    plastic_projection(ps, 0, sand);
    // Hencky strains before and after, from Eigen's SVD (not the code's).
    const Vec eps0 = Eigen::JacobiSVD<Mat>(F).singularValues().array().log().matrix();
    const Vec eps1 = Eigen::JacobiSVD<Mat>(ps.F[0]).singularValues().array().log().matrix();
    Mat tau;
    kirchhoff_stress(ps, 0, tau);
    const double trace = tau.trace();
    const double dev = (tau - Mat::Identity() * trace / D).norm();
    const double scale = 1e-9 * std::max(1.0, tau.norm());
    EXPECT_LE(dev + alpha * trace, scale) << "trial " << trial << ": outside the cone";
    // Inside: F rebuilt from its own SVD, equal to rounding.
    const double moved = (ps.F[0] - F).norm();
    if (moved < 1e-12) {
      ++inside;
      EXPECT_EQ(ps.q[0], q0);
    } else {
      // Both strain lists sorted descending: the projection keeps the order.
      EXPECT_NEAR(ps.q[0] - q0, (eps0 - eps1).norm(), 1e-9) << "trial " << trial;
      if (tau.norm() < 1e-9) ++tip; else ++projected;
    }
  }
  // The sample covers all three cases.
  EXPECT_GT(inside, 50);
  EXPECT_GT(projected, 50);
  EXPECT_GT(tip, 50);
}

TEST(Constitutive, SandReturnMappingStaysInTheCone2D) { check_return_mapping<2>(11); }
TEST(Constitutive, SandReturnMappingStaysInTheCone3D) { check_return_mapping<3>(12); }

}  // namespace
}  // namespace loom::mpm
