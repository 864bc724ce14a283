// Plugin author API. Rotations as people type them: Euler angles in degrees.
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace loom::numerics {

// R = R_z(γ) R_y(β) R_x(α) for degrees (α, β, γ): about x first, then y,
// then z (fixed axes), the convention of the scene's Object node.
inline Eigen::Matrix3d rotation_from_degrees(const Eigen::Vector3d& degrees) {
  const Eigen::Vector3d r = degrees * (M_PI / 180);
  return (Eigen::AngleAxisd(r.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(r.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace loom::numerics
