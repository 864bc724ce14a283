// Plugin author API. Small SVDs for local steps (ARAP) and distortion metrics.
#pragma once

#include <Eigen/Core>

#include "loom/export.hpp"

namespace loom::numerics {

// Singular values σ1 >= σ2 >= 0 of a 2×2 matrix, closed form.
LOOM_API Eigen::Vector2d singular_values_2x2(const Eigen::Matrix2d& A);

// The rotation R (det R = +1) closest to A in the Frobenius norm: R = U V^T,
// with the sign of the last singular vector flipped when det(U V^T) < 0.
LOOM_API Eigen::Matrix2d closest_rotation_2x2(const Eigen::Matrix2d& A);
LOOM_API Eigen::Matrix3d closest_rotation_3x3(const Eigen::Matrix3d& A);

}  // namespace loom::numerics
