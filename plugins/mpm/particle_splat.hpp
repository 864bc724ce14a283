// Particles splatted to an image: the 2D visualization of the solver (and an
// orthographic preview of 3D states). Each particle is an anti-aliased disc of
// its colour; in 3D the farther particles are drawn first.
#pragma once

#include <opencv2/core.hpp>

#include "mpm_state.hpp"

namespace loom::mpm {

enum class View { front, top, side };  // 3D: looking along −z, −y, or −x

struct SplatOptions {
  int width = 512;          // pixels; the image is square (the domain is)
  double size = 1;          // the domain edge: [0, size] maps to the image
  double radius_px = 1.0;   // disc radius in pixels
  Eigen::Vector3f background = Eigen::Vector3f(0.02f, 0.02f, 0.03f);
  View view = View::front;
};

// CV_32FC3, linear RGB; image x = domain x, image y = −domain y (up is up).
cv::Mat splat(const MpmState& state, const SplatOptions& options);

}  // namespace loom::mpm
