// Per-triangle isometric 2D frames and cotangent weights, the fixed data of
// Liu et al. 2008 (§3: each triangle flattened isometrically into its own frame).
#pragma once

#include <Eigen/Core>

namespace loom::arap {

// For triangle t with corners x_t^0, x_t^1, x_t^2 (rows of F):
//   D      #F by 6  local-frame edge vectors d_t^i = x_t^i − x_t^{i+1}, i = 0..2,
//                   stored as (x, y) pairs: D(t, 2i), D(t, 2i+1)
//   cot    #F by 3  weight c_t^i of edge (i, i+1): cot θ_t^i, θ_t^i the angle
//                   opposite that edge (at corner i+2)
//   area   #F       triangle areas
// A degenerate triangle (twice its area <= 1e-8 × its longest edge², so a
// cotangent would be infinite or huge) gets the small uniform weights
// kDegenerateWeight instead: finite, nonnegative, and it keeps its vertices
// connected so the global systems stay positive definite.
struct TriangleFrames {
  Eigen::MatrixXd D;
  Eigen::MatrixX3d cot;
  Eigen::VectorXd area;
  int degenerate = 0;  // how many triangles took the fallback weights
};

inline constexpr double kDegenerateWeight = 1e-6;

//   V  #V by 3 positions,  F  #F by 3 triangles
TriangleFrames triangle_frames(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

}  // namespace loom::arap
