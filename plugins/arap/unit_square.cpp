#include "unit_square.hpp"

#include <algorithm>
#include <limits>

namespace loom::arap {

Eigen::MatrixX2d fit_unit_square(const Eigen::MatrixX2d& UV, const std::vector<bool>& used) {
  Eigen::RowVector2d lo = Eigen::RowVector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::RowVector2d hi = -lo;
  for (Eigen::Index v = 0; v < UV.rows(); ++v)
    if (used[v]) lo = lo.cwiseMin(UV.row(v)), hi = hi.cwiseMax(UV.row(v));
  Eigen::MatrixX2d out = Eigen::MatrixX2d::Zero(UV.rows(), 2);
  if (!(lo.array() <= hi.array()).all()) return out;
  const double extent = (hi - lo).maxCoeff();
  const double scale = extent > 0 ? 1 / extent : 1;
  for (Eigen::Index v = 0; v < UV.rows(); ++v)
    if (used[v]) out.row(v) = (UV.row(v) - lo) * scale;
  return out;
}

}  // namespace loom::arap
