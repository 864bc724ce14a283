// Boundary loops, adjacency and referenced vertices on meshes built in code.
#include <gtest/gtest.h>

#include "loom/error.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "test_meshes.hpp"

namespace loom::numerics {
namespace {

// Twice the signed area enclosed by a loop of planar vertices (shoelace).
double signed_area2(const Eigen::MatrixX3d& V, const std::vector<int>& loop) {
  double a = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const int p = loop[i], q = loop[(i + 1) % loop.size()];
    a += V(p, 0) * V(q, 1) - V(q, 0) * V(p, 1);
  }
  return a;
}

TEST(MeshTopology, GridHasOneCounterClockwiseLoop) {
  const auto m = test::grid(4, 3);
  const auto loops = boundary_loops(m.F);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 14u);
  EXPECT_NEAR(signed_area2(m.V, loops[0]), 2.0, 1e-12);  // the unit square, counter-clockwise
  for (int v : loops[0]) {
    const double x = m.V(v, 0), y = m.V(v, 1);
    EXPECT_TRUE(x == 0 || x == 1 || y == 0 || y == 1) << "interior vertex " << v << " in the loop";
  }
}

TEST(MeshTopology, DiskLoopIsTheOuterRing) {
  const auto m = test::disk(5, 24);
  const auto loops = boundary_loops(m.F);
  ASSERT_EQ(loops.size(), 1u);
  ASSERT_EQ(loops[0].size(), 24u);
  for (int v : loops[0]) EXPECT_NEAR(m.V.row(v).norm(), 1.0, 1e-12);
  EXPECT_GT(signed_area2(m.V, loops[0]), 0);
}

TEST(MeshTopology, AnnulusHasOuterAndInnerLoopsOppositelyOriented) {
  const auto m = test::annulus(4, 20, 0.4);
  const auto loops = boundary_loops(m.F);
  ASSERT_EQ(loops.size(), 2u);
  EXPECT_EQ(loops[0].size(), 20u);
  EXPECT_EQ(loops[1].size(), 20u);
  const double a0 = signed_area2(m.V, loops[0]), a1 = signed_area2(m.V, loops[1]);
  EXPECT_LT(a0 * a1, 0);  // the hole runs the other way
  const auto& outer = a0 > 0 ? loops[0] : loops[1];
  for (int v : outer) EXPECT_NEAR(m.V.row(v).norm(), 1.0, 1e-12);
}

TEST(MeshTopology, SeveralHolesSortedLongestFirst) {
  // 12×12 grid without cells (2,2), (8,3) and the 2×2 block at (5,7)..(6,8).
  const auto m = test::grid(12, 12, [](int i, int j) {
    if (i == 2 && j == 2) return false;
    if (i == 8 && j == 3) return false;
    if ((i == 5 || i == 6) && (j == 7 || j == 8)) return false;
    return true;
  });
  const auto loops = boundary_loops(m.F);
  ASSERT_EQ(loops.size(), 4u);
  EXPECT_EQ(loops[0].size(), 48u);
  EXPECT_EQ(loops[1].size(), 8u);
  EXPECT_EQ(loops[2].size(), 4u);
  EXPECT_EQ(loops[3].size(), 4u);
  EXPECT_GT(signed_area2(m.V, loops[0]), 0);
  for (size_t k = 1; k < loops.size(); ++k) EXPECT_LT(signed_area2(m.V, loops[k]), 0);
}

TEST(MeshTopology, ClosedMeshHasNoLoop) {
  Eigen::MatrixX3i F(4, 3);
  F << 0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3;  // a tetrahedron
  EXPECT_TRUE(boundary_loops(F).empty());
}

TEST(MeshTopology, NonManifoldEdgeIsNamed) {
  Eigen::MatrixX3i F(3, 3);
  F << 0, 1, 2, 1, 0, 3, 0, 1, 4;  // three faces on edge (0, 1)
  try {
    boundary_loops(F);
    FAIL() << "no error";
  } catch (const loom::Error& e) {
    EXPECT_NE(std::string(e.what()).find("non-manifold edge (0, 1)"), std::string::npos) << e.what();
  }
}

TEST(MeshTopology, AdjacencyAndReferencedVertices) {
  Eigen::MatrixX3i F(2, 3);
  F << 0, 1, 2, 0, 2, 3;  // vertex 4 is unreferenced
  const auto adj = vertex_adjacency(F, 5);
  EXPECT_EQ(adj[0], (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(adj[1], (std::vector<int>{0, 2}));
  EXPECT_EQ(adj[2], (std::vector<int>{0, 1, 3}));
  EXPECT_TRUE(adj[4].empty());
  EXPECT_EQ(referenced_vertices(F, 5), (std::vector<bool>{true, true, true, true, false}));
}

TEST(MeshTopology, ConnectedComponentsThroughSharedVertices) {
  // Two pieces: {0,1,2,5} (two triangles sharing vertex 2... and 5) and {3,4,6};
  // vertex 7 is in no face. Numbered by each piece's lowest vertex.
  Eigen::MatrixX3i F(3, 3);
  F << 3, 4, 6, 0, 1, 2, 2, 5, 0;
  int count = 0;
  const auto c = connected_components(F, 8, &count);
  EXPECT_EQ(count, 2);
  EXPECT_EQ(c, (std::vector<int>{0, 0, 0, 1, 1, 0, 1, -1}));
  EXPECT_EQ(connected_components(Eigen::MatrixX3i(0, 3), 2), (std::vector<int>{-1, -1}));
}

}  // namespace
}  // namespace loom::numerics
