// Building systems: spring counts, rest lengths and lumped masses against
// closed-form counts, areas and volumes.
#include <gtest/gtest.h>

#include "cloth_test_systems.hpp"
#include "loom/error.hpp"
#include "mass_spring.hpp"

namespace loom::cloth {
namespace {

TEST(MassSpring, GridClothCountsAndMass) {
  const int n = 7;
  SpringSystem s = grid_cloth(n, n, Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 0, 0),
                              Eigen::Vector3d(0, 3, 0), 0.5, 10, 20, 30);
  const int structural = 2 * n * (n - 1), shear = 2 * (n - 1) * (n - 1), bend = 2 * n * (n - 2);
  EXPECT_EQ(s.spring_count(), structural + shear + bend);
  EXPECT_EQ((s.stiffness.array() == 10).count(), structural);
  EXPECT_EQ((s.stiffness.array() == 20).count(), shear);
  EXPECT_EQ((s.stiffness.array() == 30).count(), bend);
  EXPECT_NEAR(s.mass.sum(), 0.5 * 2 * 3, 1e-12);  // density × area
  for (int e = 0; e < s.spring_count(); ++e)
    EXPECT_NEAR(s.rest_length[e], (s.X.row(s.springs(e, 0)) - s.X.row(s.springs(e, 1))).norm(), 1e-15);
  EXPECT_NO_THROW(require_valid(s));
}

TEST(MassSpring, MeshSpringsOnEdgesAndAcrossInteriorEdges) {
  // Two triangles sharing one edge: 5 edges, 1 bending spring between 1 and 3.
  Eigen::MatrixX3d V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  Eigen::MatrixX3i F(2, 3);
  F << 0, 1, 2, 0, 2, 3;
  const SpringSystem s = mesh_springs(V, F, 2.0, 100, 5);
  ASSERT_EQ(s.spring_count(), 6);
  EXPECT_EQ((s.stiffness.array() == 5).count(), 1);
  for (int e = 0; e < 6; ++e)
    if (s.stiffness[e] == 5) {
      EXPECT_EQ(s.springs.row(e).minCoeff(), 1);
      EXPECT_EQ(s.springs.row(e).maxCoeff(), 3);
      EXPECT_NEAR(s.rest_length[e], std::sqrt(2.0), 1e-15);
    }
  EXPECT_NEAR(s.mass.sum(), 2.0 * 1.0, 1e-12);
}

TEST(MassSpring, CuboidLatticeSpringClassesAndMass) {
  const int nx = 3, ny = 4, nz = 5;
  const SpringSystem s = cuboid_lattice(nx, ny, nz, Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 3, 4),
                                        1000, 1, 2, 3);
  const int cells = (nx - 1) * (ny - 1) * (nz - 1);
  const int edges = (nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1);
  const int faces = 2 * ((nx - 1) * (ny - 1) * nz + (nx - 1) * ny * (nz - 1) + nx * (ny - 1) * (nz - 1));
  EXPECT_EQ((s.stiffness.array() == 1).count(), edges);
  EXPECT_EQ((s.stiffness.array() == 2).count(), faces);
  EXPECT_EQ((s.stiffness.array() == 3).count(), 4 * cells);
  EXPECT_NEAR(s.mass.sum(), 1000 * 2 * 3 * 4, 1e-9);
  // A closed surface: 2 triangles per boundary quad, every edge shared twice.
  EXPECT_EQ(s.F.rows(), 4 * ((nx - 1) * (ny - 1) + (nx - 1) * (nz - 1) + (ny - 1) * (nz - 1)));
  EXPECT_NO_THROW(require_valid(s));
}

TEST(MassSpring, FixingByIndexAndBox) {
  SpringSystem s = test::curtain(5, 10);
  EXPECT_EQ(s.fixed_count(), 5);  // the top row
  fix_vertices(s, {0}, Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(s.fixed_count(), 6);
  EXPECT_THROW(fix_vertices(s, {25}, Eigen::Vector3d::Ones(), Eigen::Vector3d::Zero()), Error);
  EXPECT_THROW(fix_vertices(s, {-1}, Eigen::Vector3d::Ones(), Eigen::Vector3d::Zero()), Error);
}

TEST(MassSpring, InvalidSystemsAreNamed) {
  SpringSystem s = test::curtain(3, 10);
  s.stiffness[0] = -1;
  EXPECT_THROW(require_valid(s), Error);
  s = test::curtain(3, 10);
  s.springs(0, 1) = s.springs(0, 0);
  EXPECT_THROW(require_valid(s), Error);
  s = test::curtain(3, 10);
  s.mass[0] = 0;
  EXPECT_THROW(require_valid(s), Error);
  EXPECT_THROW(grid_cloth(1, 5, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 1, 1, 1, 1),
               Error);
}

}  // namespace
}  // namespace loom::cloth
