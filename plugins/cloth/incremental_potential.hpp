// The incremental potential of one implicit Euler step (Liu et al. 2013,
// eq. 2; the assignment's eq. (37)):
//   E(x) = ½ (x − y)ᵀ M (x − y) + h² Σ_s ½ k_s (‖x_s1 − x_s2‖ − l_s)²,
//   y = x_n + h v_n + h² M⁻¹ f_ext.
// Its minimizer solves g(x) = M(x − y) − h² f_int(x) = 0, the implicit step.
// Positions are #V by 3; fixed vertices are not unknowns (their gradient rows
// are zero and they stay where x has them).
#pragma once

#include <Eigen/Core>

#include "mass_spring.hpp"

namespace loom::cloth {

// Σ_s ½ k_s (‖r_s‖ − l_s)², the springs' elastic energy.
double spring_energy(const SpringSystem& s, const Eigen::MatrixX3d& x);
// f_int(x) = −∇ spring_energy, #V by 3 (fixed rows included).
Eigen::MatrixX3d spring_forces(const SpringSystem& s, const Eigen::MatrixX3d& x);

double incremental_potential(const SpringSystem& s, const Eigen::MatrixX3d& x,
                             const Eigen::MatrixX3d& y, double h);
// ∇E(x) = M(x − y) − h² f_int(x), with the rows of fixed vertices zero.
Eigen::MatrixX3d incremental_gradient(const SpringSystem& s, const Eigen::MatrixX3d& x,
                                      const Eigen::MatrixX3d& y, double h);

// Kinetic + elastic + gravitational energy: ½ Σ m‖v‖² + Σ ½k(‖r‖−l)² − Σ m g·x.
double total_energy(const SpringSystem& s, const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& v,
                    const Eigen::Vector3d& gravity);

}  // namespace loom::cloth
