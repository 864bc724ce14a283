// Tutte's embedding with uniform weights, the classic initialization of ARAP.
#pragma once

#include <Eigen/Core>

namespace loom::arap {

// In every connected part, the longest boundary loop is laid on a circle of
// the loop's own length (chord-length spacing, so the scale is the mesh's)
// and every other vertex is the average of its neighbours:
// Σ_j w_ij (u_j − u_i) = 0 with w_ij from numerics::uniform_weights. Parts are
// placed side by side along u. Throws loom::Error when a part has no boundary.
//   V #V by 3, F #F by 3; returns UV #V by 2 (vertices of no face at 0)
Eigen::MatrixX2d tutte_map(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

}  // namespace loom::arap
