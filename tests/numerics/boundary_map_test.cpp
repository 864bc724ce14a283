// The boundary lands exactly on the circle or the square, spaced by arc length.
#include <cmath>

#include <gtest/gtest.h>

#include "loom/numerics/boundary_map.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "test_meshes.hpp"

namespace loom::numerics {
namespace {

TEST(BoundaryMap, CircleByArcLength) {
  auto m = test::grid(6, 3);  // a 1 by 1 square with unequal edge lengths along x and y
  m.V.col(0) *= 3.0;
  const auto loop = boundary_loops(m.F)[0];
  const Eigen::MatrixX2d B = map_boundary(m.V, m.F, loop, BoundaryShape::circle);
  double total = 0;
  for (size_t k = 0; k < loop.size(); ++k) total += (m.V.row(loop[(k + 1) % loop.size()]) - m.V.row(loop[k])).norm();
  double s = 0;
  for (size_t k = 0; k < loop.size(); ++k) {
    EXPECT_NEAR((B.row(k) - Eigen::RowVector2d(0.5, 0.5)).norm(), 0.5, 1e-15);
    const double angle = std::atan2(B(k, 1) - 0.5, B(k, 0) - 0.5);
    EXPECT_NEAR(std::remainder(angle - 2 * M_PI * s / total, 2 * M_PI), 0.0, 1e-12);
    s += (m.V.row(loop[(k + 1) % loop.size()]) - m.V.row(loop[k])).norm();
  }
}

TEST(BoundaryMap, SquareCornersAndSides) {
  const auto m = test::disk(4, 40);
  const auto loop = boundary_loops(m.F)[0];
  const Eigen::MatrixX2d B = map_boundary(m.V, m.F, loop, BoundaryShape::square);
  int corners = 0;
  for (int k = 0; k < B.rows(); ++k) {
    const double u = B(k, 0), v = B(k, 1);
    EXPECT_TRUE(u == 0 || u == 1 || v == 0 || v == 1) << k << ": " << u << ", " << v;
    EXPECT_TRUE(u >= 0 && u <= 1 && v >= 0 && v <= 1);
    corners += (u == 0 || u == 1) && (v == 0 || v == 1);
  }
  EXPECT_EQ(corners, 4);
  // 40 equal edges: ten per side, each a tenth of the side.
  for (int k = 0; k < B.rows(); ++k)
    EXPECT_NEAR((B.row((k + 1) % B.rows()) - B.row(k)).norm(), 0.1, 1e-12);
}

TEST(BoundaryMap, SquareCornersTakeTheEars) {
  // A grid's two corner triangles with all three vertices on the boundary
  // sit at (1,0) and (0,1); a corner elsewhere would flatten them.
  const auto m = test::grid(7, 5);
  const auto loop = boundary_loops(m.F)[0];
  const auto corners = square_corners(m.V, m.F, loop);
  ASSERT_EQ(corners.size(), 4u);
  int ears = 0;
  for (int c : corners) {
    const Eigen::RowVector3d p = m.V.row(loop[c]);
    ears += (p - Eigen::RowVector3d(1, 0, 0)).norm() < 1e-12 || (p - Eigen::RowVector3d(0, 1, 0)).norm() < 1e-12;
  }
  EXPECT_EQ(ears, 2);
}

}  // namespace
}  // namespace loom::numerics
