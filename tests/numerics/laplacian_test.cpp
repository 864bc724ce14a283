// Laplacian weights against hand-computed values and the linear precision of
// planar meshes: for x linear in position, Σ_j w_ij (x_j - x_i) = 0 at every
// interior vertex.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "loom/numerics/laplacian.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "test_meshes.hpp"

namespace loom::numerics {
namespace {

std::vector<bool> interior_vertices(const Eigen::MatrixX3i& F, int n) {
  std::vector<bool> interior = referenced_vertices(F, n);
  for (const auto& loop : boundary_loops(F))
    for (int v : loop) interior[v] = false;
  return interior;
}

// A planar disk with jittered interior vertices: a mix of acute and obtuse triangles.
test::TestMesh jittered_disk(double amount) {
  auto m = test::disk(8, 32);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-amount, amount);
  const auto interior = interior_vertices(m.F, static_cast<int>(m.V.rows()));
  for (int v = 0; v < m.V.rows(); ++v)
    if (interior[v]) m.V.row(v) += Eigen::RowVector3d(u(rng), u(rng), 0);
  return m;
}

// A sheared grid: every cell is cut into one acute and one obtuse triangle.
test::TestMesh sheared_grid() {
  auto m = test::grid(10, 10);
  m.V.col(0) += 1.6 * m.V.col(1);
  return m;
}

void expect_linear_precision(const SparseMatrix& W, const test::TestMesh& m, double tol) {
  const Eigen::VectorXd x = 0.3 + 2.0 * m.V.col(0).array() - 1.5 * m.V.col(1).array();
  const Eigen::VectorXd Lx = W * x - Eigen::VectorXd(W * Eigen::VectorXd::Ones(x.size())).cwiseProduct(x);
  const auto interior = interior_vertices(m.F, static_cast<int>(m.V.rows()));
  for (int v = 0; v < x.size(); ++v) {
    if (!interior[v]) continue;
    EXPECT_NEAR(Lx[v], 0.0, tol) << "vertex " << v;
  }
}

TEST(Laplacian, CotangentWeightsOfARightTriangle) {
  Eigen::MatrixX3d V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  Eigen::MatrixX3i F(1, 3);
  F << 0, 1, 2;
  const SparseMatrix W = cotangent_weights(V, F);
  // Opposite edge (1,2): the right angle, cot 90° = 0. Opposite (0,2) and
  // (0,1): 45°, cot 45° = 1, halved.
  EXPECT_NEAR(W.coeff(1, 2), 0.0, 1e-15);
  EXPECT_NEAR(W.coeff(0, 2), 0.5, 1e-15);
  EXPECT_NEAR(W.coeff(0, 1), 0.5, 1e-15);
  EXPECT_NEAR(W.coeff(2, 0), 0.5, 1e-15);
  EXPECT_EQ(W.coeff(0, 0), 0.0);
}

// A hexagon of six equilateral triangles around vertex 0 (edge length 2):
// spokes border two faces, w = 2 · cot 60° / 2 = 1/√3; rim edges one, 1/(2√3).
test::TestMesh hexagon() {
  test::TestMesh m;
  m.V.resize(7, 3);
  m.V.row(0) << 0, 0, 0;
  for (int k = 0; k < 6; ++k) m.V.row(k + 1) << 2 * std::cos(k * M_PI / 3), 2 * std::sin(k * M_PI / 3), 0;
  m.F.resize(6, 3);
  for (int k = 0; k < 6; ++k) m.F.row(k) << 0, k + 1, (k + 1) % 6 + 1;
  return m;
}

TEST(Laplacian, CotangentWeightsOfAnEquilateralMesh) {
  const auto m = hexagon();
  for (const SparseMatrix& W : {cotangent_weights(m.V, m.F), intrinsic_delaunay_cotangent_weights(m.V, m.F)}) {
    for (int k = 1; k <= 6; ++k) {
      EXPECT_NEAR(W.coeff(0, k), 1 / std::sqrt(3.0), 1e-14);
      EXPECT_NEAR(W.coeff(k, k % 6 + 1), 0.5 / std::sqrt(3.0), 1e-14);
    }
    EXPECT_NEAR(W.sum(), 2 * (6 / std::sqrt(3.0) + 3 / std::sqrt(3.0)), 1e-12);
  }
}

TEST(Laplacian, UniformWeightsAreOnePerEdge) {
  const auto m = hexagon();
  const SparseMatrix W = uniform_weights(m.F, 7);
  EXPECT_EQ(W.nonZeros(), 24);  // 12 edges, both directions
  EXPECT_EQ(W.coeff(0, 3), 1.0);
  EXPECT_EQ(W.coeff(1, 2), 1.0);
  EXPECT_EQ(W.coeff(1, 3), 0.0);
}

TEST(Laplacian, MeanValueWeightsOfAnEquilateralMesh) {
  // At the centre each spoke sees two 60° angles: w = 2 tan 30° / 2.
  const auto m = hexagon();
  const SparseMatrix W = mean_value_weights(m.V, m.F);
  for (int k = 1; k <= 6; ++k) EXPECT_NEAR(W.coeff(0, k), std::tan(M_PI / 6), 1e-14);
}

TEST(Laplacian, LinearPrecisionOnPlanarMeshes) {
  for (const auto& m : {jittered_disk(0.01), sheared_grid()}) {
    {
      SCOPED_TRACE("cotangent");
      expect_linear_precision(cotangent_weights(m.V, m.F), m, 1e-12);
    }
    {
      SCOPED_TRACE("intrinsic Delaunay");
      expect_linear_precision(intrinsic_delaunay_cotangent_weights(m.V, m.F), m, 1e-10);
    }
    {
      SCOPED_TRACE("mean value");
      expect_linear_precision(mean_value_weights(m.V, m.F), m, 1e-12);
    }
  }
}

TEST(Laplacian, IntrinsicDelaunayWeightsAreNonnegativeWithObtuseTriangles) {
  auto m = sheared_grid();
  // Lift it onto a bumpy surface so that flips are intrinsic, not planar.
  for (int v = 0; v < m.V.rows(); ++v) m.V(v, 2) = 0.2 * std::sin(4 * m.V(v, 0)) * std::cos(3 * m.V(v, 1));
  const int n = static_cast<int>(m.V.rows());
  const auto interior = interior_vertices(m.F, n);
  const SparseMatrix C = cotangent_weights(m.V, m.F), D = intrinsic_delaunay_cotangent_weights(m.V, m.F);
  double most_negative = 0;
  for (int k = 0; k < C.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(C, k); it; ++it)
      if (interior[it.row()]) most_negative = std::min(most_negative, it.value());
  EXPECT_LT(most_negative, -0.1) << "the test mesh should have negative cotangent weights";
  for (int k = 0; k < D.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(D, k); it; ++it) {
      EXPECT_TRUE(std::isfinite(it.value()));
      if (interior[it.row()]) {
        EXPECT_GE(it.value(), -1e-12) << it.row() << "," << it.col();
      }
    }
  EXPECT_NEAR((SparseMatrix(D.transpose()) - D).norm(), 0.0, 1e-12);
}

TEST(Laplacian, DegenerateFacesGiveFiniteWeights) {
  Eigen::MatrixX3d V(5, 3);
  V << 0, 0, 0, 1, 0, 0, 2, 0, 0, 1, 1, 0, 1, 1, 0;  // vertex 4 duplicates vertex 3
  Eigen::MatrixX3i F(4, 3);
  F << 0, 1, 3, 1, 2, 3, 0, 2, 1, 4, 0, 3;  // (0 2 1) is flat, (4 0 3) has a zero edge
  for (const SparseMatrix& W : {cotangent_weights(V, F), intrinsic_delaunay_cotangent_weights(V, F),
                                mean_value_weights(V, F)})
    for (int k = 0; k < W.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(W, k); it; ++it) EXPECT_TRUE(std::isfinite(it.value()));
}

}  // namespace
}  // namespace loom::numerics
