// The closed-form 2×2 routines against Eigen's SVD.
#include <random>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <gtest/gtest.h>

#include "loom/numerics/svd.hpp"

namespace loom::numerics {
namespace {

TEST(Svd, SingularValues2x2MatchEigen) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int k = 0; k < 1000; ++k) {
    Eigen::Matrix2d A;
    A << u(rng), u(rng), u(rng), u(rng);
    Eigen::JacobiSVD<Eigen::Matrix2d> svd(A);
    Eigen::Vector2d s = singular_values_2x2(A);
    EXPECT_NEAR(s[0], svd.singularValues()[0], 1e-12);
    EXPECT_NEAR(s[1], svd.singularValues()[1], 1e-12);
  }
}

TEST(Svd, ClosestRotation2x2IsARotationAndClosest) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int k = 0; k < 200; ++k) {
    Eigen::Matrix2d A;
    A << u(rng), u(rng), u(rng), u(rng);
    Eigen::Matrix2d R = closest_rotation_2x2(A);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_NEAR((R.transpose() * R - Eigen::Matrix2d::Identity()).norm(), 0.0, 1e-12);
    for (double t = 0; t < 6.283; t += 0.05) {  // no rotation is closer
      Eigen::Matrix2d Q;
      Q << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
      EXPECT_LE((R - A).norm(), (Q - A).norm() + 1e-12);
    }
  }
}

TEST(Svd, ClosestRotation3x3HandlesReflections) {
  Eigen::Matrix3d A = Eigen::Vector3d(1, 1, -1).asDiagonal();
  Eigen::Matrix3d R = closest_rotation_3x3(A);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
}

}  // namespace
}  // namespace loom::numerics
