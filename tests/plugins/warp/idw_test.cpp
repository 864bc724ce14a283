// IDW against its defining properties: interpolation, the identity, and exact
// reproduction of an affine map when the D_i are fitted.
#include <random>

#include <gtest/gtest.h>

#include "idw.hpp"

namespace loom::warp {
namespace {

Eigen::MatrixX2d random_points(int n, unsigned seed, double extent = 500) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, extent);
  Eigen::MatrixX2d P(n, 2);
  for (int i = 0; i < n; ++i) P.row(i) << u(rng), u(rng);
  return P;
}

TEST(Idw, InterpolatesTheTargets) {
  const Eigen::MatrixX2d P = random_points(40, 1), Q = random_points(40, 2);
  for (bool affine : {true, false})
    for (double mu : {0.5, 1.0, 2.0, 3.0}) {
      const IdwMap m = fit_idw(P, Q, mu, affine);
      EXPECT_LE((evaluate_idw(m, P) - Q).cwiseAbs().maxCoeff(), 1e-12) << "mu " << mu;
    }
}

TEST(Idw, IdentityPairsGiveTheIdentity) {
  const Eigen::MatrixX2d P = random_points(20, 3), X = random_points(200, 4);
  const IdwMap m = fit_idw(P, P, 2, true);
  EXPECT_LE((evaluate_idw(m, X) - X).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(Idw, FittedAffinePartsReproduceAnAffineMap) {
  Eigen::Matrix2d M;
  M << 1.2, 0.3, -0.2, 0.9;
  const Eigen::Vector2d t(15, -7);
  const Eigen::MatrixX2d P = random_points(12, 5), X = random_points(300, 6);
  const Eigen::MatrixX2d Q = (P * M.transpose()).rowwise() + t.transpose();
  const IdwMap m = fit_idw(P, Q, 2, true);
  const Eigen::MatrixX2d expected = (X * M.transpose()).rowwise() + t.transpose();
  EXPECT_LE((evaluate_idw(m, X) - expected).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(Idw, FewPointsAreDefined) {
  const Eigen::MatrixX2d none(0, 2), X = random_points(50, 7);
  EXPECT_EQ(evaluate_idw(fit_idw(none, none, 2, true), X), X);
  Eigen::MatrixX2d P(1, 2), Q(1, 2);
  P << 10, 20;
  Q << 13, 16;
  // One point, fitted D = I: a translation by q − p.
  const Eigen::MatrixX2d shifted = X.rowwise() + Eigen::RowVector2d(3, -4);
  EXPECT_LE((evaluate_idw(fit_idw(P, Q, 2, true), X) - shifted).cwiseAbs().maxCoeff(), 1e-9);
  // Two points: identity across their line, never NaN.
  Eigen::MatrixX2d P2(2, 2), Q2(2, 2);
  P2 << 0, 0, 10, 0;
  Q2 << 0, 0, 20, 0;
  EXPECT_TRUE(evaluate_idw(fit_idw(P2, Q2, 2, true), X).allFinite());
}

}  // namespace
}  // namespace loom::warp
