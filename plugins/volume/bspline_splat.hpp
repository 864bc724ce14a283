// Points splatted onto a voxel lattice with the quadratic B-spline of MLS-MPM
// (Hu et al. 2018, as mpm88 and MPMStep compute it): the kernel
// MPMStep's P2G uses, so a density grid with voxel_size = Δx is the grid mass
// MPM itself sees, divided by the cell volume.
#pragma once

#include <array>

#include <Eigen/Core>

#include "loom/point_set.hpp"
#include "volume.hpp"

namespace loom::volume {

// The 3 weights and the lowest node along one axis of a point at x (in voxel
// units, nodes at integers): base = ⌊x − ½⌋, f = x − base,
// w = ½(1.5 − f)², ¾ − (f − 1)², ½(f − ½)². They sum to 1 (partition of unity).
struct AxisWeights {
  int base;
  std::array<double, 3> w;
};
AxisWeights quadratic_bspline(double x);

// density_i = Σ_p w_ip m_p / h³ and velocity_i = Σ_p w_ip m_p v_p / Σ_p w_ip m_p
// (the mass-weighted average, P2G's momentum over mass), h = voxel_size.
// `mass` and `velocity` are #P and #P×3 (velocity may be empty: no grid).
// Sums run in point order on one thread, so the grids do not depend on the
// thread count.
Volume splat_points(const Eigen::MatrixX3d& positions, const Eigen::VectorXd& mass, const Eigen::MatrixX3d& velocity,
                    double voxel_size);

}  // namespace loom::volume
