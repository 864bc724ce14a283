// Radial basis function interpolation of a plane map (the ImageWarping
// assignment's RBF):
//
//   f(x) = A x + b + Σ_i a_i g_i(‖x − p_i‖),   f(p_j) = q_j for all j.
//
// Kernels:
//   multiquadric  g_i(d) = (d² + r_i²)^(μ/2), r_i = distance from p_i to the
//                 nearest other source (μ = 1: the assignment's multiquadric,
//                 μ = −1: inverse multiquadric). The affine part is fitted
//                 first by the assignment's rule (fit_affine_part) and the
//                 a_i interpolate what it leaves: (G + λI) a = Q − (P Aᵀ + b).
//   thin_plate    g(d) = d² log d, with A, b solved jointly under the side
//                 conditions Σ a_i = 0, Σ a_i p_iᵀ = 0 (Bookstein 1989):
//                 [G + λI  P₁; P₁ᵀ 0] [a; (b A)ᵀ] = [Q; 0], P₁ = [1 P].
// λ ≥ 0 trades exact interpolation for smoothness (λ = 0: f(p_i) = q_i).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace loom::warp {

enum class RbfKernel { multiquadric, thin_plate };

struct RbfMap {
  Eigen::Matrix2d A = Eigen::Matrix2d::Identity();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  Eigen::MatrixX2d p;  // #n by 2 centers (the sources)
  Eigen::MatrixX2d a;  // #n by 2 coefficients
  Eigen::VectorXd r2;  // #n squared shape radii r_i² (multiquadric)
  RbfKernel kernel = RbfKernel::multiquadric;
  double mu = 1;
};

// The affine part by the assignment's rule:
//   0 points: identity; 1: translation; 2: translation and uniform scale
//   (‖q₂−q₁‖/‖p₂−p₁‖, about the midpoints); 3 or more: least squares (exact
//   for 3 points in general position). Collinear sources fall back to the
//   2-point rule on the two extreme points of the line.
//   P, Q  #n by 2 distinct sources and targets
//   A     2 by 2, b  2: the map x ↦ A x + b
void fit_affine_part(const Eigen::MatrixX2d& P, const Eigen::MatrixX2d& Q, Eigen::Matrix2d& A,
                     Eigen::Vector2d& b);

// Fits the RBF map. A kernel system that is singular (μ = 0 or 2 make G low
// rank; collinear sources under thin_plate) is solved in the least-squares
// sense with minimum norm instead, and a line saying so is added to *notes.
//   P, Q  #n by 2 sources and targets, distinct sources (see clean_control_points)
RbfMap fit_rbf(const Eigen::MatrixX2d& P, const Eigen::MatrixX2d& Q, RbfKernel kernel, double mu,
               double lambda, std::vector<std::string>* notes);

// f along one row: fx[j], fy[j] = f(x[j], y) for j < n.
void evaluate_rbf_row(const RbfMap& m, double y, const double* x, int n, double* fx, double* fy);

// f at points: X #X by 2 → #X by 2.
Eigen::MatrixX2d evaluate_rbf(const RbfMap& m, const Eigen::MatrixX2d& X);

}  // namespace loom::warp
