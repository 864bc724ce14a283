#include "weights.hpp"

#include <algorithm>

#include "loom/error.hpp"
#include "loom/numerics/laplacian.hpp"

namespace loom::parameterize {

const std::vector<std::string>& weight_names() {
  static const std::vector<std::string> names = {"uniform",           "cotangent",  "cotangent_clamped",
                                               "intrinsic_delaunay", "mean_value", "shape_preserving"};
  return names;
}

Weights parse_weights(const std::string& name) {
  for (size_t k = 0; k < weight_names().size(); ++k)
    if (weight_names()[k] == name) return static_cast<Weights>(k);
  throw Error("unknown weights \"" + name + "\"");
}

Eigen::SparseMatrix<double> weight_matrix(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights) {
  switch (weights) {
    case Weights::uniform: return numerics::uniform_weights(F, static_cast<int>(V.rows()));
    case Weights::cotangent: return numerics::cotangent_weights(V, F);
    case Weights::cotangent_clamped: {
      // Clamping at a small fraction of the mean magnitude keeps every weight
      // positive (Floater 2003, Tutte's theorem: the map cannot fold) while
      // changing only the obtuse-dominated edges.
      Eigen::SparseMatrix<double> W = numerics::cotangent_weights(V, F);
      const double floor = 1e-3 * W.cwiseAbs().sum() / std::max<Eigen::Index>(W.nonZeros(), 1);
      for (Eigen::Index k = 0; k < W.nonZeros(); ++k) W.valuePtr()[k] = std::max(W.valuePtr()[k], floor);
      return W;
    }
    case Weights::intrinsic_delaunay: return numerics::intrinsic_delaunay_cotangent_weights(V, F);
    case Weights::mean_value: return numerics::mean_value_weights(V, F);
    case Weights::shape_preserving: return shape_preserving_weights(V, F);
  }
  throw Error("unknown weights");
}

}  // namespace loom::parameterize
