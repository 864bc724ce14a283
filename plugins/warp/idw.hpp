// Inverse distance weighted interpolation of a plane map (Shepard; the
// ImageWarping assignment's IDW):
//
//   f(x) = Σ_i w_i(x) f_i(x),   f_i(x) = q_i + D_i (x − p_i),
//   w_i(x) = σ_i(x) / Σ_j σ_j(x),   σ_i(x) = 1 / ‖x − p_i‖^μ,
//
// so f(p_i) = q_i. D_i is the local affine part fitted by weighted least squares
// (below) or zero, which makes f a weighted mean of the targets.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace loom::warp {

struct IdwMap {
  Eigen::MatrixX2d p;              // #n by 2 sources
  Eigen::MatrixX2d q;              // #n by 2 targets
  std::vector<Eigen::Matrix2d> D;  // n local affine parts
  double mu = 2;                   // weight exponent μ > 0
};

// Fits the IDW map. With fit_affine, D_i minimizes (assignment eq. for D_i)
//   Σ_{j≠i} σ_i(p_j) ‖q_i + D_i (p_j − p_i) − q_j‖² + ε ‖D_i − I‖²_F
// with ε = 1e-9 · Σ_{j≠i} σ_i(p_j) ‖p_j − p_i‖²: negligible when the p_j span
// the plane, and the identity along directions they do not span (collinear
// points; D_i = I when i has no other point), so the fit is never singular.
//   P, Q  #n by 2 sources and targets, distinct sources (see clean_control_points)
IdwMap fit_idw(const Eigen::MatrixX2d& P, const Eigen::MatrixX2d& Q, double mu, bool fit_affine);

// f along one row: fx[j], fy[j] = f(x[j], y) for j < n. With no control points
// f is the identity. Exact at the sources: f(p_i) = q_i.
void evaluate_idw_row(const IdwMap& m, double y, const double* x, int n, double* fx, double* fy);

// f at points: X #X by 2 → #X by 2.
Eigen::MatrixX2d evaluate_idw(const IdwMap& m, const Eigen::MatrixX2d& X);

}  // namespace loom::warp
