#include "weights.hpp"

#include <algorithm>

#include "loom/error.hpp"
#include "loom/numerics/laplacian.hpp"

namespace loom::parameterize {

const std::vector<std::pair<Weights, std::string>>& weight_choices() {
  static const std::vector<std::pair<Weights, std::string>> choices = {
      {Weights::uniform, "uniform"},
      {Weights::cotangent, "cotangent"},
      {Weights::cotangent_clamped, "cotangent_clamped"},
      {Weights::intrinsic_delaunay, "intrinsic_delaunay"},
      {Weights::mean_value, "mean_value"},
      {Weights::shape_preserving, "shape_preserving"}};
  return choices;
}

const std::vector<std::string>& weight_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (const auto& choice : weight_choices()) list.push_back(choice.second);
    return list;
  }();
  return names;
}

Eigen::SparseMatrix<double> weight_matrix(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights,
                                          const std::function<void()>& check) {
  switch (weights) {
    case Weights::uniform: return numerics::uniform_weights(F, static_cast<int>(V.rows()));
    case Weights::cotangent: return numerics::cotangent_weights(V, F, check);
    case Weights::cotangent_clamped: {
      // Clamping at a small fraction of the mean magnitude keeps every weight
      // positive (Floater 2003, Tutte's theorem: the map cannot fold) while
      // changing only the obtuse-dominated edges.
      Eigen::SparseMatrix<double> W = numerics::cotangent_weights(V, F, check);
      const double floor = 1e-3 * W.cwiseAbs().sum() / std::max<Eigen::Index>(W.nonZeros(), 1);
      for (Eigen::Index k = 0; k < W.nonZeros(); ++k) W.valuePtr()[k] = std::max(W.valuePtr()[k], floor);
      return W;
    }
    case Weights::intrinsic_delaunay: return numerics::intrinsic_delaunay_cotangent_weights(V, F);
    case Weights::mean_value: return numerics::mean_value_weights(V, F, check);
    case Weights::shape_preserving: return shape_preserving_weights(V, F);
  }
  throw Error("unknown weights");
}

}  // namespace loom::parameterize
