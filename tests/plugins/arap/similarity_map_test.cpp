// ASAP against analytic cases and against the un-eliminated system of
// Liu et al. eqs. 24–28 (u and every (a_t, b_t) as unknowns), solved densely.
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "arap_test_meshes.hpp"
#include "loom/error.hpp"
#include "loom/numerics/laplacian.hpp"
#include "similarity_map.hpp"

namespace loom::arap {
namespace {

TEST(TriangleFrames, CotangentsMatchTheNumericsLaplacian) {
  const auto m = test::cap(5, 16);
  const TriangleFrames fr = triangle_frames(m.V, m.F);
  const numerics::SparseMatrix W = numerics::cotangent_weights(m.V, m.F);
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(m.V.rows(), m.V.rows());
  for (Eigen::Index t = 0; t < m.F.rows(); ++t)
    for (int i = 0; i < 3; ++i) {
      const int a = m.F(t, i), b = m.F(t, (i + 1) % 3);
      sum(a, b) += fr.cot(t, i) / 2, sum(b, a) += fr.cot(t, i) / 2;
      // Local frames are isometric: edge lengths are kept.
      const double local = fr.D.block<1, 2>(t, 2 * i).norm();
      EXPECT_NEAR(local, (m.V.row(a) - m.V.row(b)).norm(), 1e-14);
    }
  EXPECT_LT((sum - Eigen::MatrixXd(W)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(fr.degenerate, 0);
}

TEST(SimilarityMap, PlanarMeshMapsByASimilarity) {
  const auto flat = test::irregular_grid(12, 1, false);
  const auto tilted = test::irregular_grid(12, 1, true);
  const auto map = similarity_map(triangle_frames(tilted.V, tilted.F), tilted.F,
                                  int(tilted.V.rows()), similarity_pins(tilted.V, tilted.F, {}));
  EXPECT_LT(test::fit_residual(flat.V.leftCols<2>(), map.UV, true), 1e-10);
  EXPECT_LT(map.energy, 1e-12);  // 0 but for rounding; the area is 1
}

TEST(SimilarityMap, MatchesTheFullSystemInUAndSimilarities) {
  const auto m = test::cap(4, 10);
  const int n = int(m.V.rows()), nf = int(m.F.rows());
  const TriangleFrames fr = triangle_frames(m.V, m.F);
  const std::vector<Pin> pins = similarity_pins(m.V, m.F, {0, 25});
  const auto map = similarity_map(fr, m.F, n, pins);

  // E = ½ Σ c ‖e − L d‖² with z = (u_0, v_0, ..., a_0, b_0, ...): H = Σ c g gᵀ.
  const int dim = 2 * n + 2 * nf;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(dim, dim);
  for (int t = 0; t < nf; ++t)
    for (int i = 0; i < 3; ++i) {
      const int a = m.F(t, i), b = m.F(t, (i + 1) % 3);
      const double c = fr.cot(t, i), dx = fr.D(t, 2 * i), dy = fr.D(t, 2 * i + 1);
      Eigen::VectorXd gx = Eigen::VectorXd::Zero(dim), gy = gx;
      gx[2 * a] = 1, gx[2 * b] = -1, gx[2 * n + 2 * t] = -dx, gx[2 * n + 2 * t + 1] = dy;
      gy[2 * a + 1] = 1, gy[2 * b + 1] = -1, gy[2 * n + 2 * t] = -dy, gy[2 * n + 2 * t + 1] = -dx;
      H += c * (gx * gx.transpose() + gy * gy.transpose());
    }
  std::vector<int> fixed_dofs;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(dim);
  for (const Pin& p : pins)
    for (int k = 0; k < 2; ++k) fixed_dofs.push_back(2 * p.vertex + k), z[2 * p.vertex + k] = p.uv[k];
  std::vector<int> free_dofs;
  for (int k = 0; k < dim; ++k)
    if (std::find(fixed_dofs.begin(), fixed_dofs.end(), k) == fixed_dofs.end()) free_dofs.push_back(k);
  const Eigen::MatrixXd Hff = H(free_dofs, free_dofs);
  const Eigen::VectorXd rhs = -H(free_dofs, fixed_dofs) * z(fixed_dofs);
  z(free_dofs) = Hff.fullPivLu().solve(rhs);
  for (int v = 0; v < n; ++v) {
    EXPECT_NEAR(map.UV(v, 0), z[2 * v], 1e-9);
    EXPECT_NEAR(map.UV(v, 1), z[2 * v + 1], 1e-9);
  }
  EXPECT_NEAR(map.energy, 0.5 * z.dot(H * z), 1e-9 * (1 + map.energy));
}

TEST(SimilarityMap, GivenPinsAreCheckedAndHeld) {
  const auto m = test::cap(3, 8);
  EXPECT_THROW(similarity_pins(m.V, m.F, {1}), Error);
  EXPECT_THROW(similarity_pins(m.V, m.F, {2, 2}), Error);
  EXPECT_THROW(similarity_pins(m.V, m.F, {0, 1000}), Error);
  const auto pins = similarity_pins(m.V, m.F, {3, 7});
  const auto map = similarity_map(triangle_frames(m.V, m.F), m.F, int(m.V.rows()), pins);
  for (const Pin& p : pins) EXPECT_LT((map.UV.row(p.vertex).transpose() - p.uv).norm(), 1e-15);
}

}  // namespace
}  // namespace loom::arap
