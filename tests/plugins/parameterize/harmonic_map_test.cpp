// Fixed-boundary maps against independent references: linear precision on
// planar meshes, a dense solve, flat minimal surfaces, and degenerate input.
#include <cmath>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "generators.hpp"
#include "harmonic_map.hpp"
#include "loom/error.hpp"
#include "loom/numerics/distortion.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "test_meshes.hpp"

namespace loom::parameterize {
namespace {

using numerics::test::TestMesh;

std::vector<int> boundary_of(const Eigen::MatrixX3i& F) {
  std::vector<int> b;
  for (const auto& loop : numerics::boundary_loops(F)) b.insert(b.end(), loop.begin(), loop.end());
  return b;
}

// A planar disk with jittered interior vertices (acute and obtuse triangles).
TestMesh jittered_disk() {
  // Radial moves of ±0.03 between rings 0.1 apart, angular of ±1/4 of the
  // spacing: the mesh stays an embedding.
  auto m = numerics::test::disk(10, 48);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<char> on_boundary(m.V.rows(), 0);
  for (int v : boundary_of(m.F)) on_boundary[v] = 1;
  for (int v = 1; v < m.V.rows(); ++v) {
    if (on_boundary[v]) continue;
    const double r = m.V.row(v).norm() + 0.03 * u(rng);
    const double t = std::atan2(m.V(v, 1), m.V(v, 0)) + 0.25 * (2 * M_PI / 48) * u(rng);
    m.V.row(v) << r * std::cos(t), r * std::sin(t), 0;
  }
  return m;
}

// A bumpy, sheared grid: many obtuse triangles, cotangent weights go negative.
TestMesh bumpy_sheared_grid() {
  auto m = numerics::test::grid(16, 16);
  m.V.col(0) += 1.6 * m.V.col(1);
  for (int v = 0; v < m.V.rows(); ++v) m.V(v, 2) = 0.3 * std::sin(5 * m.V(v, 0)) * std::cos(4 * m.V(v, 1));
  return m;
}

// HemisphereMesh's shape with ±2% radial noise.
TestMesh noisy_hemisphere(int rings, int segments) {
  std::mt19937_64 rng(9);
  return generate::hemisphere_mesh(1, rings, segments, 0.02, rng);
}

TEST(HarmonicMap, PlanarMeshIsReproducedFromItsOwnBoundary) {
  // Linear precision: with the boundary at its own positions, every weight
  // that reproduces linear functions returns the mesh itself.
  const auto m = jittered_disk();
  const Eigen::MatrixXd X0 = m.V.leftCols<2>();
  for (Weights w : {Weights::cotangent, Weights::intrinsic_delaunay, Weights::mean_value, Weights::shape_preserving}) {
    const auto s = numerics::solve_fixed_boundary(weight_matrix(m.V, m.F, w), m.F, boundary_of(m.F), X0);
    EXPECT_LT((s.X - X0).cwiseAbs().maxCoeff(), 1e-10) << weight_names()[static_cast<int>(w)];
  }
}

TEST(HarmonicMap, PlanarDiskStaysASimilarityUnderTheCotangentMap) {
  // A round disk with equal boundary edges: its circle boundary is a
  // similarity of its own, so the harmonic map is that similarity.
  const auto m = jittered_disk();
  const Parameterization p = parameterize(m.V, m.F, Weights::cotangent, numerics::BoundaryShape::circle);
  const Eigen::MatrixX2d X = m.V.leftCols<2>().rowwise() - m.V.leftCols<2>().colwise().mean();
  const Eigen::MatrixX2d U = p.UV.rowwise() - p.UV.colwise().mean();
  const Eigen::Matrix2d A = X.colPivHouseholderQr().solve(U);  // U ≈ X A
  EXPECT_LT((X * A - U).cwiseAbs().maxCoeff(), 1e-10);
  const Eigen::Matrix2d AtA = A.transpose() * A;
  EXPECT_NEAR(AtA(0, 0), 0.25, 1e-12);  // scale 1/2: the unit disk into the circle of radius 1/2
  EXPECT_NEAR(AtA(1, 1), 0.25, 1e-12);
  EXPECT_NEAR(AtA(0, 1), 0.0, 1e-12);
  EXPECT_GT(A.determinant(), 0);
}

TEST(HarmonicMap, UniformMapEqualsADenseSolve) {
  const auto m = noisy_hemisphere(5, 14);
  const int n = static_cast<int>(m.V.rows());
  const auto loop = numerics::boundary_loops(m.F)[0];
  const Parameterization p = parameterize(m.V, m.F, Weights::uniform, numerics::BoundaryShape::circle);
  // The dense system: L = D - A on every row, identity rows on the boundary.
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n), B = Eigen::MatrixXd::Zero(n, 2);
  const auto adj = numerics::vertex_adjacency(m.F, n);
  for (int v = 0; v < n; ++v) {
    L(v, v) = static_cast<double>(adj[v].size());
    for (int u : adj[v]) L(v, u) = -1;
  }
  for (int v : loop) {
    L.row(v).setZero();
    L(v, v) = 1;
    B.row(v) = p.UV.row(v);  // the boundary is tested on its own in boundary_map_test
  }
  const Eigen::MatrixXd X = L.fullPivLu().solve(B);
  EXPECT_LT((X - p.UV).cwiseAbs().maxCoeff(), 1e-12);
}

// Mean-value weights are not symmetric: the map goes through the LU, solved
// without iterative refinement for these positive weights.
TEST(HarmonicMap, MeanValueMapEqualsADenseSolve) {
  const auto m = noisy_hemisphere(6, 17);
  const int n = static_cast<int>(m.V.rows());
  const auto loop = numerics::boundary_loops(m.F)[0];
  const Parameterization p = parameterize(m.V, m.F, Weights::mean_value, numerics::BoundaryShape::circle);
  EXPECT_EQ(p.solver, "umfpack");
  // Floater 2003: w_ij = (tan(α/2) + tan(β/2)) / |x_j - x_i|, α and β
  // the angles at x_i of the two faces on edge ij, each from acos.
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n), B = Eigen::MatrixXd::Zero(n, 2);
  for (int f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int i = m.F(f, k), j = m.F(f, (k + 1) % 3), l = m.F(f, (k + 2) % 3);
      const Eigen::RowVector3d a = m.V.row(j) - m.V.row(i), b = m.V.row(l) - m.V.row(i);
      const double t = std::tan(std::acos(a.dot(b) / (a.norm() * b.norm())) / 2);
      L(i, j) -= t / a.norm();
      L(i, l) -= t / b.norm();
      L(i, i) += t / a.norm() + t / b.norm();
    }
  for (int v : loop) {
    L.row(v).setZero();
    L(v, v) = 1;
    B.row(v) = p.UV.row(v);
  }
  const Eigen::MatrixXd X = L.fullPivLu().solve(B);
  EXPECT_LT((X - p.UV).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(HarmonicMap, ConvexCombinationsNeverFold) {
  const std::vector<TestMesh> meshes = {jittered_disk(), bumpy_sheared_grid(), noisy_hemisphere(12, 40)};
  for (const auto& m : meshes)
    for (Weights w : {Weights::uniform, Weights::mean_value, Weights::cotangent_clamped, Weights::shape_preserving})
      for (numerics::BoundaryShape shape : {numerics::BoundaryShape::circle, numerics::BoundaryShape::square}) {
        const Parameterization p = parameterize(m.V, m.F, w, shape);
        EXPECT_TRUE(p.UV.allFinite());
        EXPECT_EQ(numerics::distortion(m.V, m.F, p.UV).flipped, 0)
            << weight_names()[static_cast<int>(w)]
            << (shape == numerics::BoundaryShape::circle ? " circle" : " square");
      }
}

TEST(HarmonicMap, RobustCotangentVariantsFoldLess) {
  // A very noisy hemisphere: plain cotangent weights fold it; intrinsic
  // Delaunay weights fold it less (the intrinsic triangulation's map cannot
  // fold, the mesh's own triangles still can); clamped weights never do.
  auto m = noisy_hemisphere(20, 60);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int v = 0; v < m.V.rows(); ++v) m.V.row(v) *= 1 + u(rng);
  auto flips = [&](Weights w) {
    return numerics::distortion(m.V, m.F, parameterize(m.V, m.F, w, numerics::BoundaryShape::circle).UV).flipped;
  };
  const int cot = flips(Weights::cotangent), idt = flips(Weights::intrinsic_delaunay);
  EXPECT_GT(cot, 0) << "the test mesh should fold under plain cotangent weights";
  EXPECT_LT(idt, cot);
  EXPECT_EQ(flips(Weights::cotangent_clamped), 0);
}

TEST(HarmonicMap, MinimalSurfaceOfAPlanarBoundaryIsFlat) {
  auto m = noisy_hemisphere(8, 32);
  for (int v : boundary_of(m.F)) m.V(v, 2) = 0;  // the equator: a planar boundary
  for (Weights w : {Weights::uniform, Weights::cotangent}) {
    const Eigen::MatrixX3d X = minimal_surface(m.V, m.F, w, 3);
    EXPECT_LT(X.col(2).cwiseAbs().maxCoeff(), 1e-10) << weight_names()[static_cast<int>(w)];
    for (int v : boundary_of(m.F)) EXPECT_EQ(X.row(v), m.V.row(v));
  }
}

TEST(HarmonicMap, ClosedNonManifoldAndDisconnectedMeshesAreRefused) {
  Eigen::MatrixX3d V = Eigen::MatrixX3d::Random(5, 3);
  Eigen::MatrixX3i tetra(4, 3);
  tetra << 0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3;
  EXPECT_THROW(parameterize(V, tetra, Weights::uniform, numerics::BoundaryShape::circle), Error);
  EXPECT_THROW(minimal_surface(V, tetra, Weights::uniform, 1), Error);
  Eigen::MatrixX3i fin(3, 3);
  fin << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  EXPECT_THROW(parameterize(V, fin, Weights::uniform, numerics::BoundaryShape::circle), Error);
  // A disk plus a separate closed tetrahedron.
  auto m = numerics::test::disk(3, 12);
  const int n = static_cast<int>(m.V.rows());
  Eigen::MatrixX3d V2(n + 4, 3);
  V2 << m.V, Eigen::MatrixX3d::Random(4, 3);
  Eigen::MatrixX3i F2(m.F.rows() + 4, 3);
  F2 << m.F, (tetra.array() + n).matrix();
  try {
    parameterize(V2, F2, Weights::uniform, numerics::BoundaryShape::circle);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("connected piece"), std::string::npos) << e.what();
  }
}

TEST(HarmonicMap, DegenerateInputGivesFiniteUVs) {
  auto m = numerics::test::disk(4, 16);
  const int n = static_cast<int>(m.V.rows());
  // An unreferenced vertex, a duplicate of boundary vertex 49 closing a
  // zero-area face on the boundary edge (49, 50), and a vertex collapsed
  // onto its neighbour.
  Eigen::MatrixX3d V(n + 2, 3);
  V << m.V, Eigen::RowVector3d(9, 9, 9), m.V.row(49);
  V.row(1) = V.row(2);
  Eigen::MatrixX3i F(m.F.rows() + 1, 3);
  F << m.F, Eigen::RowVector3i(50, 49, n + 1);
  for (Weights w : {Weights::uniform, Weights::cotangent, Weights::cotangent_clamped, Weights::intrinsic_delaunay,
                    Weights::mean_value, Weights::shape_preserving}) {
    const Parameterization p = parameterize(V, F, w, numerics::BoundaryShape::circle);
    EXPECT_TRUE(p.UV.allFinite()) << weight_names()[static_cast<int>(w)];
    EXPECT_EQ(p.unreferenced, 1);
    const auto r = numerics::distortion(V, F, p.UV);
    EXPECT_TRUE(std::isfinite(r.angle_mean) && std::isfinite(r.arap_energy));
  }
}

}  // namespace
}  // namespace loom::parameterize
