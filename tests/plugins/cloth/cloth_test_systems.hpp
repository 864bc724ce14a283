// Small systems shared by the cloth tests.
#pragma once

#include <memory>

#include "mass_spring.hpp"

namespace loom::cloth::test {

// A vertical curtain of n by n vertices, 1 m wide, in the x-y plane with its
// top row (y = 0.5) fixed; 0.1 kg/m².
inline SpringSystem curtain(int n, double k, bool pin_top = true) {
  SpringSystem s = grid_cloth(n, n, Eigen::Vector3d(-0.5, -0.5, 0), Eigen::Vector3d(1, 0, 0),
                              Eigen::Vector3d(0, 1, 0), 0.1, k, k, k);
  if (pin_top) fix_vertices(s, {}, Eigen::Vector3d(-1, 0.49, -1), Eigen::Vector3d(1, 1, 1));
  return s;
}

inline std::shared_ptr<const SpringSystem> shared(SpringSystem s) {
  return std::make_shared<const SpringSystem>(std::move(s));
}

}  // namespace loom::cloth::test
