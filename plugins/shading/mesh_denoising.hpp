// Mesh denoising through a displacement map (the assignment's eqs. 44-45),
// and the smoothing flows it is compared with.
//
//   V #V by 3 positions, F #F by 3 triangles, N #V by 3 unit vertex normals,
//   UV #V by 2 texture coordinates in [0, 1]² (v up).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace loom::shading {

// Eq. 44-45: δ_i = p_i - (1/|N(i)|) Σ_{j in N(i)} p_j, d_i = <δ_i, n_i>; 0 on
// boundary vertices (kept fixed) and isolated ones.   -> #V
Eigen::VectorXd normal_displacements(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                     const Eigen::MatrixX3d& N);

struct DisplacementMap {
  cv::Mat image;      // CV_32FC1 in [0, 1], top row at v = 1
  double scale = 1;   // d = offset + scale * texel
  double offset = 0;
};

// Bakes per-vertex values d into a size x size map in UV space: each texel
// gets the inverse-squared-distance average of its K nearest vertices in UV
// (a uniform grid finds them), then the map is scaled to [0, 1].
DisplacementMap bake_displacement(const Eigen::MatrixX2d& UV, const Eigen::VectorXd& d, int size, int K);

// The map read back at the vertices' UVs (bilinear), in scene units.
Eigen::VectorXd sample_displacement(const DisplacementMap& map, const Eigen::MatrixX2d& UV);

// p_i - d_i n_i (eq. 45 applied: the noise along the normal removed).
Eigen::MatrixX3d remove_displacement(const Eigen::MatrixX3d& V, const Eigen::MatrixX3d& N,
                                     const Eigen::VectorXd& d);

// Explicit smoothing flow, `steps` times p_i += lambda (Σ w_ij p_j / Σ w_ij - p_i)
// with uniform weights (Laplacian smoothing) or cotangent weights (clamped at 0;
// mean-curvature flow), recomputed each step; boundary vertices fixed.
enum class SmoothingWeights { uniform, cotangent };
Eigen::MatrixX3d smooth(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, SmoothingWeights weights,
                        int steps, double lambda);

// Error of a mesh against a clean one with the same connectivity: RMS of the
// vertex distances, and the mean angle (radians) between face normals.
struct SurfaceError {
  double rms_distance = 0, mean_normal_angle = 0;
};
SurfaceError surface_error(const Eigen::MatrixX3d& V, const Eigen::MatrixX3d& clean, const Eigen::MatrixX3i& F);

}  // namespace loom::shading
