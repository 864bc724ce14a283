// Primary rays of a pinhole or orthographic Camera through an image of
// width × height pixels (origin top-left, y down, as every Loom image).
#pragma once

#include <cmath>

#include "loom/scene.hpp"
#include "sampling.hpp"

namespace loom::pathtrace {

struct CameraRays {
  Vec3f eye, forward, right, up;
  float tan_half = 1, ortho_half = 1, aspect = 1;
  bool ortho = false;
  CameraRays(const Camera& c, int width, int height) {
    eye = c.eye.cast<float>();
    forward = (c.target - c.eye).cast<float>();
    if (!(forward.squaredNorm() > 0)) forward = Vec3f(0, 0, -1);
    forward.normalize();
    right = forward.cross(c.up.cast<float>());
    if (!(right.squaredNorm() > 1e-12f))
      right = forward.cross(std::fabs(forward.y()) < 0.9f ? Vec3f(0, 1, 0) : Vec3f(1, 0, 0));
    right.normalize();
    up = right.cross(forward);
    tan_half = std::tan(float(c.fov_y) / 2);
    ortho_half = float(c.ortho_height) / 2;
    aspect = float(width) / float(height);
    ortho = c.projection == Camera::Projection::orthographic;
  }
  // (sx, sy) in [-1, 1]², y up.
  void ray(float sx, float sy, Vec3f* origin, Vec3f* dir) const {
    if (ortho) {
      *origin = eye + ortho_half * (sx * aspect * right + sy * up);
      *dir = forward;
    } else {
      *origin = eye;
      *dir = unit(forward + tan_half * (sx * aspect * right + sy * up));
    }
  }
};

}  // namespace loom::pathtrace
