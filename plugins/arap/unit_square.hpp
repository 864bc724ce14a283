// The Mesh convention for UVs: inside [0,1]².
#pragma once

#include <vector>

#include <Eigen/Core>

namespace loom::arap {

// The same map moved and uniformly scaled (aspect kept) so its bounding box
// touches [0,1]² at the origin and on its longer side. Rows not `used`
// (vertices of no face) are set to 0 and do not count.
//   UV #V by 2; used #V: false for rows to ignore
Eigen::MatrixX2d fit_unit_square(const Eigen::MatrixX2d& UV, const std::vector<bool>& used);

}  // namespace loom::arap
