// RBF against its defining properties: interpolation to 1e-9, the
// assignment's affine rule, exact reproduction of affine pairs, and defined
// behaviour when the kernel system is singular.
#include <random>

#include <gtest/gtest.h>

#include "rbf.hpp"

namespace loom::warp {
namespace {

Eigen::MatrixX2d random_points(int n, unsigned seed, double extent = 1000) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, extent);
  Eigen::MatrixX2d P(n, 2);
  for (int i = 0; i < n; ++i) P.row(i) << u(rng), u(rng);
  return P;
}

double relative_error(const Eigen::MatrixX2d& F, const Eigen::MatrixX2d& Q) {
  return (F - Q).cwiseAbs().maxCoeff() / Q.cwiseAbs().maxCoeff();
}

TEST(Rbf, InterpolatesTheTargetsTo1e9) {
  const Eigen::MatrixX2d P = random_points(64, 1);
  const Eigen::MatrixX2d Q = P + 30 * random_points(64, 2, 1);
  for (double mu : {1.0, -1.0, 0.5}) {
    std::vector<std::string> notes;
    const RbfMap m = fit_rbf(P, Q, RbfKernel::multiquadric, mu, 0, &notes);
    EXPECT_TRUE(notes.empty());
    EXPECT_LE(relative_error(evaluate_rbf(m, P), Q), 1e-9) << "mu " << mu;
  }
  const RbfMap tps = fit_rbf(P, Q, RbfKernel::thin_plate, 1, 0, nullptr);
  EXPECT_LE(relative_error(evaluate_rbf(tps, P), Q), 1e-9);
}

TEST(Rbf, AffineRuleForFewPoints) {
  Eigen::Matrix2d A;
  Eigen::Vector2d b;
  Eigen::MatrixX2d P1(1, 2), Q1(1, 2);
  P1 << 5, 5;
  Q1 << 8, 1;
  fit_affine_part(P1, Q1, A, b);
  EXPECT_EQ(A, Eigen::Matrix2d::Identity());
  EXPECT_TRUE(b.isApprox(Eigen::Vector2d(3, -4)));
  // Two points: uniform scale ‖q₂−q₁‖/‖p₂−p₁‖ = 2, midpoint to midpoint.
  Eigen::MatrixX2d P2(2, 2), Q2(2, 2);
  P2 << 0, 0, 10, 0;
  Q2 << 1, 1, 1, 21;
  fit_affine_part(P2, Q2, A, b);
  EXPECT_TRUE(A.isApprox(2 * Eigen::Matrix2d::Identity()));
  EXPECT_TRUE((A * Eigen::Vector2d(5, 0) + b).isApprox(Eigen::Vector2d(1, 11)));
  // Three collinear points fall back to the two-point rule on the extremes.
  Eigen::MatrixX2d P3(3, 2), Q3(3, 2);
  P3 << 0, 0, 5, 5, 10, 10;
  Q3 << 0, 0, 10, 10, 20, 20;
  fit_affine_part(P3, Q3, A, b);
  EXPECT_TRUE(A.isApprox(2 * Eigen::Matrix2d::Identity()));
  EXPECT_TRUE(A.allFinite() && b.allFinite());
}

TEST(Rbf, AffinePairsAreReproducedByTheAffinePart) {
  Eigen::Matrix2d M;
  M << 0.8, -0.4, 0.3, 1.1;
  const Eigen::Vector2d t(-12, 40);
  const Eigen::MatrixX2d P = random_points(30, 3), X = random_points(500, 4);
  const Eigen::MatrixX2d Q = (P * M.transpose()).rowwise() + t.transpose();
  const Eigen::MatrixX2d expected = (X * M.transpose()).rowwise() + t.transpose();
  for (RbfKernel k : {RbfKernel::multiquadric, RbfKernel::thin_plate}) {
    const RbfMap m = fit_rbf(P, Q, k, 1, 0, nullptr);
    EXPECT_TRUE(m.A.isApprox(M, 1e-10));
    EXPECT_TRUE(m.b.isApprox(t, 1e-10));
    EXPECT_LE(m.a.cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_LE((evaluate_rbf(m, X) - expected).cwiseAbs().maxCoeff(), 1e-6);
  }
}

TEST(Rbf, SingularKernelSystemsFallBackToLeastSquares) {
  const Eigen::MatrixX2d P = random_points(20, 5);
  const Eigen::MatrixX2d Q = P + 10 * random_points(20, 6, 1);
  std::vector<std::string> notes;
  // μ = 2: g = d² + r² is a quadratic polynomial, so G has rank ≤ 4.
  const RbfMap m = fit_rbf(P, Q, RbfKernel::multiquadric, 2, 0, &notes);
  EXPECT_EQ(notes.size(), 1u);
  EXPECT_TRUE(evaluate_rbf(m, random_points(100, 7)).allFinite());
  // Collinear sources under the thin plate: the side conditions are singular.
  Eigen::MatrixX2d L(5, 2), LQ(5, 2);
  for (int i = 0; i < 5; ++i) {
    L.row(i) << 10.0 * i, 10.0 * i;
    LQ.row(i) << 10.0 * i + (i % 2), 10.0 * i;
  }
  notes.clear();
  const RbfMap line = fit_rbf(L, LQ, RbfKernel::thin_plate, 1, 0, &notes);
  EXPECT_TRUE(evaluate_rbf(line, random_points(100, 8)).allFinite());
}

TEST(Rbf, RegularizationSmoothsWithoutInterpolating) {
  const Eigen::MatrixX2d P = random_points(30, 9);
  const Eigen::MatrixX2d Q = P + 20 * random_points(30, 10, 1);
  const RbfMap exact = fit_rbf(P, Q, RbfKernel::multiquadric, 1, 0, nullptr);
  const RbfMap smooth = fit_rbf(P, Q, RbfKernel::multiquadric, 1, 1e4, nullptr);
  EXPECT_LT(smooth.a.norm(), exact.a.norm());
  EXPECT_TRUE(evaluate_rbf(smooth, P).allFinite());
}

}  // namespace
}  // namespace loom::warp
