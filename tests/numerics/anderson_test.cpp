// Anderson mixing on linear fixed-point maps G(u) = A u + b, whose fixed
// point u* = (I − A)⁻¹ b is solved independently by Eigen's LU. For a linear
// map Anderson with a window as long as the dimension is GMRES in disguise
// (Walker and Ni 2011): it reaches u* in about n + 1 steps, where the plain
// iteration with spectral radius 0.99 has hardly begun.
#include <cmath>
#include <random>

#include <Eigen/LU>
#include <Eigen/QR>
#include <gtest/gtest.h>

#include "loom/numerics/anderson.hpp"

namespace loom::numerics {
namespace {

struct LinearMap {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
};

// A = Q diag(λ) Qᵀ, λ spread over [0.5, 0.99]: a contraction with a slow mode.
LinearMap slow_contraction(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd R(n, n);
  for (int i = 0; i < R.size(); ++i) R.data()[i] = normal(rng);
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(R).householderQ();
  Eigen::VectorXd lambda = Eigen::VectorXd::LinSpaced(n, 0.5, 0.99);
  LinearMap map{Q * lambda.asDiagonal() * Q.transpose(), Eigen::VectorXd(n)};
  for (int i = 0; i < n; ++i) map.b[i] = normal(rng);
  return map;
}

TEST(Anderson, ReachesTheFixedPointOfALinearMapInAboutDimensionSteps) {
  const int n = 6;
  const LinearMap map = slow_contraction(n, 5);
  const Eigen::VectorXd exact = (Eigen::MatrixXd::Identity(n, n) - map.A).lu().solve(map.b);
  AndersonMixing mixing(n, n);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n), plain = u;
  for (int k = 0; k < n + 2; ++k) {
    u = mixing.extrapolate(u, Eigen::VectorXd(map.A * u + map.b));
    plain = map.A * plain + map.b;
  }
  EXPECT_LT((u - exact).norm(), 1e-8 * exact.norm());
  EXPECT_GT((plain - exact).norm(), 0.5 * exact.norm());  // 0.99^8 of the slow mode is left
}

TEST(Anderson, WindowZeroIsThePlainIterationAndResetForgetsTheHistory) {
  const int n = 4;
  const LinearMap map = slow_contraction(n, 6);
  AndersonMixing off(0, n), mixing(3, n), fresh(3, n);
  Eigen::VectorXd u = Eigen::VectorXd::Ones(n);
  const Eigen::VectorXd g = map.A * u + map.b;
  EXPECT_EQ(off.extrapolate(u, g), g);
  EXPECT_FALSE(mixing.active());
  Eigen::VectorXd v = u;
  for (int k = 0; k < 3; ++k) v = mixing.extrapolate(v, Eigen::VectorXd(map.A * v + map.b));
  EXPECT_TRUE(mixing.active());
  // After reset() the next two steps are those of a new mixer from there.
  mixing.reset();
  Eigen::VectorXd a = v, c = v;
  for (int k = 0; k < 2; ++k) {
    a = mixing.extrapolate(a, Eigen::VectorXd(map.A * a + map.b));
    c = fresh.extrapolate(c, Eigen::VectorXd(map.A * c + map.b));
  }
  EXPECT_EQ(a, c);
}

TEST(Anderson, AcceptsMatrixShapedIterates) {
  // Cloth's iterates are #V by 3 (column-major): the same numbers as a vector.
  const LinearMap map = slow_contraction(6, 7);
  AndersonMixing as_matrix(3, 6), as_vector(3, 6);
  Eigen::MatrixX3d U = Eigen::MatrixX3d::Zero(2, 3);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(6);
  for (int k = 0; k < 5; ++k) {
    const Eigen::VectorXd gu = map.A * u + map.b;
    Eigen::MatrixX3d G(2, 3);
    Eigen::Map<Eigen::VectorXd>(G.data(), 6) = map.A * Eigen::Map<const Eigen::VectorXd>(U.data(), 6) + map.b;
    U = as_matrix.extrapolate(U, G);
    u = as_vector.extrapolate(u, gu);
    EXPECT_EQ(Eigen::Map<const Eigen::VectorXd>(U.data(), 6), u);
  }
}

}  // namespace
}  // namespace loom::numerics
