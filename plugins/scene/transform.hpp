// Object-to-world transforms from the Object node's inputs, and the degree
// inputs of the scene nodes (radians inside, degrees where people type them).
#pragma once

#include <Eigen/Core>

namespace loom::scene {

constexpr double kPi = 3.14159265358979323846;
inline double radians(double degrees) { return degrees * kPi / 180; }

// T * R * S: scale first, then rotate about x, then y, then z (degrees), then
// translate. Throws loom::Error on a zero or non-finite scale.
Eigen::Matrix4d object_transform(const Eigen::Vector3d& translate, const Eigen::Vector3d& rotate_degrees,
                                 const Eigen::Vector3d& scale);

// v / |v|; throws loom::Error naming `what` when v is zero or not finite.
Eigen::Vector3d unit(const Eigen::Vector3d& v, const char* what);

}  // namespace loom::scene
