// Degenerate input: zero-area and very obtuse triangles, many boundaries,
// several parts, a single triangle, a closed surface. Defined results, no NaN.
#include <gtest/gtest.h>

#include "arap_test_meshes.hpp"
#include "local_global.hpp"
#include "loom/error.hpp"
#include "similarity_map.hpp"
#include "tutte_map.hpp"

namespace loom::arap {
namespace {

struct Flattened {
  Eigen::MatrixX2d asap, arap;
  std::vector<double> energy;
};

Flattened flatten(const test::TestMesh& m, bool tutte = false) {
  const int n = int(m.V.rows());
  Flattened f;
  f.asap = similarity_map(triangle_frames(m.V, m.F), m.F, n, similarity_pins(m.V, m.F, {})).UV;
  const ArapSystem sys = arap_system(m.V, m.F, {});
  ArapOptions o;
  o.max_iterations = 100;
  const ArapResult r = arap(sys, tutte ? tutte_map(m.V, m.F) : f.asap, o);
  f.arap = r.UV;
  f.energy = r.energy;
  return f;
}

void expect_sane(const Flattened& f) {
  EXPECT_TRUE(f.asap.allFinite());
  EXPECT_TRUE(f.arap.allFinite());
  for (size_t k = 1; k < f.energy.size(); ++k) {
    EXPECT_TRUE(std::isfinite(f.energy[k]));
    EXPECT_LE(f.energy[k], f.energy[k - 1] + 1e-12 * f.energy[0] + 1e-20);
  }
}

TEST(Robustness, ZeroAreaTriangles) {
  auto m = numerics::test::grid(6, 6);
  m.V.row(8) = (m.V.row(7) + m.V.row(9)) / 2;  // collinear with its row neighbours
  m.V.row(16) = m.V.row(17);                   // two vertices at one point
  Eigen::MatrixX3i F(m.F.rows() + 1, 3);
  F << m.F, Eigen::RowVector3i(30, 30, 31);     // a face with a repeated vertex
  m.F = F;
  EXPECT_GE(triangle_frames(m.V, m.F).degenerate, 2);
  expect_sane(flatten(m));
  expect_sane(flatten(m, true));
}

TEST(Robustness, VeryObtuseTriangles) {
  // Rows squeezed to 1e-3 of the columns: angles near 180°, cotangents ≈ −1000.
  auto m = numerics::test::grid(8, 8);
  m.V.col(1) *= 1e-3;
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) m.V(v, 2) = 0.3 * m.V(v, 0) * m.V(v, 0);
  const Flattened f = flatten(m);
  expect_sane(f);
  EXPECT_LT(test::edge_length_error(m, f.arap), 1e-3);  // developable: exact but for convergence
}

TEST(Robustness, ManyBoundaries) {
  auto m = numerics::test::grid(12, 12, [](int i, int j) { return !(i % 4 == 1 && j % 4 == 1); });
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) m.V(v, 2) = std::sin(3 * m.V(v, 0)) * 0.2;
  expect_sane(flatten(m));
  expect_sane(flatten(m, true));
}

TEST(Robustness, SingleTriangleKeepsItsShape) {
  test::TestMesh m;
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 2, 0, 1, 0.5, 1, -1;
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  const Flattened f = flatten(m);
  expect_sane(f);
  EXPECT_LT(test::edge_length_error(m, f.arap), 1e-12);
  const Flattened g = flatten(m, true);
  EXPECT_LT(test::edge_length_error(m, g.arap), 1e-12);
}

TEST(Robustness, SeveralPartsAndUnusedVertices) {
  const auto a = test::cap(4, 12);
  test::TestMesh m;
  m.V.resize(2 * a.V.rows() + 1, 3);
  m.V << a.V, a.V.rowwise() + Eigen::RowVector3d(3, 0, 0), Eigen::RowVector3d(9, 9, 9);
  m.F.resize(2 * a.F.rows(), 3);
  m.F << a.F, a.F.array() + int(a.V.rows());
  const Flattened f = flatten(m, true);
  expect_sane(f);
  EXPECT_EQ(f.arap.row(m.V.rows() - 1), Eigen::RowVector2d(0, 0));
  // Both copies flatten to the same shape.
  EXPECT_LT(test::fit_residual(f.arap.topRows(a.V.rows()), f.arap.middleRows(a.V.rows(), a.V.rows()), false), 1e-6);
}

TEST(Robustness, ClosedSurface) {
  // An octahedron: no boundary. Tutte cannot start; ASAP and ARAP from it can.
  test::TestMesh m;
  m.V.resize(6, 3);
  m.V << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  m.F.resize(8, 3);
  m.F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  EXPECT_THROW(tutte_map(m.V, m.F), Error);
  expect_sane(flatten(m));
}

}  // namespace
}  // namespace loom::arap
