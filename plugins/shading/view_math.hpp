// Camera and light matrices (OpenGL conventions: the camera looks down its
// -z, clip z in [-1, 1]), and the frusta of the shadow maps.
#pragma once

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "loom/scene.hpp"

namespace loom::shading {

Eigen::Matrix4d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                        const Eigen::Vector3d& up);
Eigen::Matrix4d perspective(double fov_y, double aspect, double near_plane, double far_plane);
Eigen::Matrix4d orthographic(double left, double right, double bottom, double top,
                             double near_plane, double far_plane);
// The camera's view and projection for an image of the given aspect (w / h).
void camera_matrices(const Camera& camera, double aspect, Eigen::Matrix4d& view,
                     Eigen::Matrix4d& projection);

// What a shadow map of one light sees. The map stores a linear depth metric in
// scene units: distance along `axis` from `origin` (directional, orthographic),
// or the distance to `origin` (spot, perspective; point, a cube map: one view
// per face, in GL's face order +x -x +y -y +z -z).
struct ShadowView {
  bool cube = false, ortho = false;
  Eigen::Vector3d origin, axis;
  Eigen::Matrix4d view, projection;        // 2D maps
  std::array<Eigen::Matrix4d, 6> faces;    // cube: view of each face (projection: 90 degrees)
  double texel = 0;  // texel size in scene units: absolute (ortho) or at unit depth
  double near_plane = 0, far_plane = 0;  // ortho: the depth range along `axis` from `origin`
};

// Fits the light's map to the scene's bounds: orthographic around the bounds
// for directional lights, the cone of a spot light, a cube for point lights.
ShadowView shadow_view(const Light& light, const Eigen::AlignedBox3d& bounds, int resolution);

}  // namespace loom::shading
