// Vertex normals and UV tangents on meshes whose frames are known in closed
// form: an affinely mapped grid (dP/du, dP/dv are the map's columns) and a
// closed sphere (normals radial).
#include <cmath>

#include <gtest/gtest.h>

#include "loom/numerics/tangent_frames.hpp"
#include "test_meshes.hpp"

namespace loom::numerics {
namespace {

TEST(TangentFrames, AffineGridHasTheMapsColumnsAsTangents) {
  // P = A (u, v) + c: dP/du = A.col(0), dP/dv = A.col(1) exactly, at every vertex.
  const test::TestMesh g = test::grid(4, 3);
  Eigen::Matrix<double, 3, 2> A;
  A << 2.0, 0.5, 0.3, 1.5, -1.0, 0.25;
  const Eigen::Vector3d c(0.1, -0.2, 3);
  Eigen::MatrixX3d V(g.V.rows(), 3);
  Eigen::MatrixX2d UV(g.V.rows(), 2);
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    UV.row(i) = g.V.row(i).head<2>();
    V.row(i) = (A * UV.row(i).transpose() + c).transpose();
  }
  Eigen::MatrixX3d dPdu, dPdv;
  uv_tangents(V, g.F, UV, dPdu, dPdv);
  const Eigen::Vector3d n = A.col(0).cross(A.col(1)).normalized();
  const Eigen::MatrixX3d N = vertex_normals(V, g.F);
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    EXPECT_NEAR((dPdu.row(i).transpose() - A.col(0)).norm(), 0, 1e-12);
    EXPECT_NEAR((dPdv.row(i).transpose() - A.col(1)).norm(), 0, 1e-12);
    EXPECT_NEAR((N.row(i).transpose() - n).norm(), 0, 1e-12);
    Eigen::Vector3d T, B;
    ASSERT_TRUE(tangent_basis(n, Eigen::Vector3d(dPdu.row(i)), Eigen::Vector3d(dPdv.row(i)), &T, &B));
    EXPECT_NEAR(T.dot(n), 0, 1e-12);
    EXPECT_NEAR(B.dot(n), 0, 1e-12);
    EXPECT_NEAR(T.norm(), 1, 1e-12);
    EXPECT_NEAR(T.cross(B).dot(n), 1, 1e-12);  // right-handed: this map keeps orientation
    EXPECT_GT(T.dot(A.col(0)), 0);
    EXPECT_GT(B.dot(A.col(1)), 0);
  }
}

TEST(TangentFrames, MirroredUvsFlipTheBitangent) {
  // u running the other way: B must still follow dP/dv, so the frame is left-handed.
  const test::TestMesh g = test::grid(2, 2);
  Eigen::MatrixX2d UV(g.V.rows(), 2);
  for (Eigen::Index i = 0; i < UV.rows(); ++i) UV.row(i) << 1 - g.V(i, 0), g.V(i, 1);
  Eigen::MatrixX3d dPdu, dPdv;
  uv_tangents(g.V, g.F, UV, dPdu, dPdv);
  const Eigen::Vector3d n(0, 0, 1);
  Eigen::Vector3d T, B;
  ASSERT_TRUE(tangent_basis(n, Eigen::Vector3d(dPdu.row(4)), Eigen::Vector3d(dPdv.row(4)), &T, &B));
  EXPECT_NEAR((T - Eigen::Vector3d(-1, 0, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((B - Eigen::Vector3d(0, 1, 0)).norm(), 0, 1e-12);
}

TEST(TangentFrames, DegenerateInputsGiveNoFrame) {
  Eigen::Vector3d T(7, 7, 7), B(7, 7, 7);
  const Eigen::Vector3d n(0, 0, 1);
  EXPECT_FALSE(tangent_basis(n, Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(0, 1, 0), &T, &B));
  EXPECT_FALSE(tangent_basis(n, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1, 0), &T, &B));
  EXPECT_EQ(T, Eigen::Vector3d(7, 7, 7));
  // UVs all equal: no face has a UV triangle, tangents stay zero.
  const test::TestMesh g = test::grid(2, 2);
  Eigen::MatrixX3d dPdu, dPdv;
  uv_tangents(g.V, g.F, Eigen::MatrixX2d::Zero(g.V.rows(), 2), dPdu, dPdv);
  EXPECT_EQ(dPdu.norm(), 0);
  EXPECT_EQ(dPdv.norm(), 0);
}

TEST(TangentFrames, OctahedronNormalsAreRadial) {
  // Each vertex of the regular octahedron is surrounded symmetrically: its
  // area-weighted normal is its own direction.
  Eigen::MatrixX3d V(6, 3);
  V << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  Eigen::MatrixX3i F(8, 3);
  F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  const Eigen::MatrixX3d N = vertex_normals(V, F);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR((N.row(i) - V.row(i)).norm(), 0, 1e-12) << i;
}

}  // namespace
}  // namespace loom::numerics
