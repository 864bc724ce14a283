// Plugin author API. Distortion of a parameterization, the report every flattening node gives.
//
// Per triangle t with area A_t in 3D, the Jacobian J_t of the map from its
// isometric 2D frame to UV has singular values σ1 >= σ2; the UV mesh is scaled
// first so total UV area equals total 3D area.
#pragma once

#include <Eigen/Core>

#include "loom/value.hpp"

namespace loom::numerics {

struct DistortionReport {
  int faces = 0;
  int flipped = 0;            // det J_t <= 0 (folded or degenerate in UV)
  double angle_mean = 0;      // area-weighted mean of σ1/σ2 (1: conformal)
  double angle_max = 0;
  double area_mean = 0;       // area-weighted mean of max(σ1σ2, 1/(σ1σ2)) (1: equiareal)
  double area_max = 0;
  double arap_energy = 0;     // Σ A_t [(σ1-1)² + (σ2-1)²] / Σ A_t
};

//   V  #V by 3, F  #F by 3, UV #V by 2
LOOM_API DistortionReport distortion(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                     const Eigen::MatrixX2d& UV);
LOOM_API json to_json(const DistortionReport& r);
LOOM_API std::string to_string(const DistortionReport& r);  // one line for logs

}  // namespace loom::numerics
