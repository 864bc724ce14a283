#include "loom/numerics/svd.hpp"

#include <cmath>

#include <Eigen/LU>
#include <Eigen/SVD>

namespace loom::numerics {

// A = [a b; c d]. With E = (a+d)/2, F = (a-d)/2, G = (c+b)/2, H = (c-b)/2,
// σ1,2 = sqrt(E²+H²) ± sqrt(F²+G²) (Blinn, "Consider the lowly 2×2 matrix").
Eigen::Vector2d singular_values_2x2(const Eigen::Matrix2d& A) {
  const double E = (A(0, 0) + A(1, 1)) / 2, F = (A(0, 0) - A(1, 1)) / 2;
  const double G = (A(1, 0) + A(0, 1)) / 2, H = (A(1, 0) - A(0, 1)) / 2;
  const double Q = std::hypot(E, H), R = std::hypot(F, G);
  return {Q + R, std::abs(Q - R)};
}

// The rotation part of the polar decomposition: the closest rotation to A is
// the rotation by the angle of (a+d, c-b), the similarity part of A.
Eigen::Matrix2d closest_rotation_2x2(const Eigen::Matrix2d& A) {
  const double x = A(0, 0) + A(1, 1), y = A(1, 0) - A(0, 1);
  const double r = std::hypot(x, y);
  if (r == 0) return Eigen::Matrix2d::Identity();  // A is a pure reflection-like shear
  Eigen::Matrix2d R;
  R << x / r, -y / r, y / r, x / r;
  return R;
}

Eigen::Matrix3d closest_rotation_3x3(const Eigen::Matrix3d& A) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d& V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0) U.col(2) *= -1;
  return U * V.transpose();
}

}  // namespace loom::numerics
