#include "transform.hpp"

#include <string>

#include <Eigen/Geometry>

#include "loom/error.hpp"
#include "loom/numerics/rotation.hpp"

namespace loom::scene {

Eigen::Matrix4d object_transform(const Eigen::Vector3d& translate, const Eigen::Vector3d& rotate_degrees,
                                 const Eigen::Vector3d& scale) {
  if (!translate.allFinite() || !rotate_degrees.allFinite())
    throw Error("translate and rotate_degrees must be finite");
  if (!scale.allFinite() || (scale.array().abs() < 1e-12).any())
    throw Error("scale must be finite and non-zero on every axis");
  const Eigen::Matrix3d R = numerics::rotation_from_degrees(rotate_degrees);
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = R * scale.asDiagonal();
  T.topRightCorner<3, 1>() = translate;
  return T;
}

Eigen::Vector3d unit(const Eigen::Vector3d& v, const char* what) {
  const double n = v.norm();
  if (!std::isfinite(n) || n < 1e-12) throw Error(std::string(what) + " must be a finite, non-zero vector");
  return v / n;
}

}  // namespace loom::scene
