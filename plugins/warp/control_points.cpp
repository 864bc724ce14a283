#include "control_points.hpp"

#include <cmath>

#include "loom/error.hpp"

namespace loom::warp {

ControlPoints clean_control_points(const Eigen::MatrixX2d& P, const Eigen::MatrixX2d& Q,
                                   double merge_distance, std::vector<std::string>* notes) {
  const Eigen::Index n = P.rows();
  std::vector<Eigen::Index> kept;
  std::vector<int> members;  // how many pairs were merged into each kept one
  Eigen::MatrixX2d p(n, 2), q(n, 2);
  const double merge2 = merge_distance * merge_distance;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!P.row(i).allFinite() || !Q.row(i).allFinite()) {
      if (notes) notes->push_back("pair " + std::to_string(i) + " has a NaN or infinite coordinate: ignored");
      continue;
    }
    if (P.row(i).cwiseAbs().maxCoeff() > kMaxCoordinate || Q.row(i).cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw Error("pair " + std::to_string(i) + " has a coordinate beyond ±1e7 pixels: check its units");
    std::size_t k = 0;
    while (k < kept.size() && (p.row(k) - P.row(i)).squaredNorm() > merge2) ++k;
    if (k < kept.size()) {
      if (notes)
        notes->push_back("pair " + std::to_string(i) + " has the same source as pair " +
                         std::to_string(kept[k]) + ": merged, targets averaged");
      q.row(k) = (q.row(k) * members[k] + Q.row(i)) / (members[k] + 1);
      ++members[k];
      continue;
    }
    p.row(kept.size()) = P.row(i);
    q.row(kept.size()) = Q.row(i);
    kept.push_back(i);
    members.push_back(1);
  }
  const auto m = static_cast<Eigen::Index>(kept.size());
  return {p.topRows(m), q.topRows(m)};
}

}  // namespace loom::warp
