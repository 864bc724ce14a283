// The fixed-boundary system against a dense one written from its definition:
// A_ii = Σ_j w_ij, A_ij = −w_ij between free vertices, B_i = Σ_{j fixed} w_ij x_j.
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "loom/numerics/fixed_boundary.hpp"
#include "loom/numerics/laplacian.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "test_meshes.hpp"

namespace loom::numerics {
namespace {

void expect_system_matches_definition(const SparseMatrix& W, const Eigen::MatrixX3i& F, bool symmetric) {
  const int n = static_cast<int>(W.rows());
  const std::vector<int> fixed = boundary_loops(F)[0];
  const Eigen::MatrixXd X0 = Eigen::MatrixXd::Random(n, 2);
  const FixedBoundarySystem sys = fixed_boundary_system(W, F, fixed, X0);
  const Eigen::MatrixXd Wd(W);
  const int m = static_cast<int>(sys.A.rows());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, m), B = Eigen::MatrixXd::Zero(m, 2);
  for (int v = 0; v < n; ++v) {
    const int i = sys.index[v];
    if (i < 0) continue;
    for (int u = 0; u < n; ++u) {
      if (u == v || Wd(v, u) == 0) continue;
      A(i, i) += Wd(v, u);
      if (sys.index[u] >= 0) A(i, sys.index[u]) -= Wd(v, u);
      else B.row(i) += Wd(v, u) * X0.row(u);
    }
  }
  EXPECT_EQ(m, n - static_cast<int>(fixed.size()));
  EXPECT_LT((Eigen::MatrixXd(sys.A) - A).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((sys.B - B).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(sys.symmetric, symmetric);
  EXPECT_TRUE(sys.positive);
}

TEST(FixedBoundarySystem, UniformWeightsGiveTheSymmetricGraphLaplacian) {
  const auto m = test::disk(6, 20);
  expect_system_matches_definition(uniform_weights(m.F, static_cast<int>(m.V.rows())), m.F, true);
}

TEST(FixedBoundarySystem, MeanValueWeightsGiveANonSymmetricSystem) {
  auto m = test::disk(6, 20);
  m.V.col(2) = 0.3 * m.V.col(0).array().square();  // curved, so rows differ from columns
  expect_system_matches_definition(mean_value_weights(m.V, m.F), m.F, false);
}

}  // namespace
}  // namespace loom::numerics
