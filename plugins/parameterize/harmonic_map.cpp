#include "harmonic_map.hpp"

#include <algorithm>
#include <cmath>

#include "loom/error.hpp"
#include "loom/numerics/mesh_topology.hpp"

namespace loom::parameterize {

Parameterization parameterize(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights,
                              numerics::BoundaryShape shape, const std::function<void()>& check) {
  auto checkpoint = [&check] {
    if (check) check();
  };
  if (F.rows() == 0) throw Error("the mesh has no faces");
  const int n = static_cast<int>(V.rows());
  const auto loops = numerics::boundary_loops(F, check);
  if (loops.empty())
    throw Error("the mesh is closed (no boundary loop): a fixed-boundary map needs a disk; cut it open first");

  // Fill every loop but the longest with a fan around its centroid.
  int extra = 0, extra_faces = 0;
  for (size_t l = 1; l < loops.size(); ++l) {
    ++extra;
    extra_faces += static_cast<int>(loops[l].size());
  }
  Eigen::MatrixX3d V2(n + extra, 3);
  Eigen::MatrixX3i F2(F.rows() + extra_faces, 3);
  V2.topRows(n) = V;
  F2.topRows(F.rows()) = F;
  int f = static_cast<int>(F.rows());
  for (size_t l = 1; l < loops.size(); ++l) {
    const auto& loop = loops[l];
    const int c = n + static_cast<int>(l) - 1;
    V2.row(c).setZero();
    for (int v : loop) V2.row(c) += V.row(v) / static_cast<double>(loop.size());
    for (size_t k = 0; k < loop.size(); ++k) F2.row(f++) << loop[(k + 1) % loop.size()], loop[k], c;
  }

  const Eigen::MatrixX2d boundary = numerics::map_boundary(V, F, loops[0], shape);
  Eigen::MatrixXd X0 = Eigen::MatrixXd::Zero(n + extra, 2);
  for (size_t k = 0; k < loops[0].size(); ++k) X0.row(loops[0][k]) = boundary.row(k);
  checkpoint();
  const numerics::SparseMatrix W = weight_matrix(V2, F2, weights, check);
  checkpoint();
  const numerics::FixedBoundarySolve s = numerics::solve_fixed_boundary(W, F2, loops[0], X0, check);

  Parameterization p;
  p.UV = s.X.topRows(n);
  p.boundary_vertices = static_cast<int>(loops[0].size());
  p.holes_filled = extra;
  const std::vector<bool> used = numerics::referenced_vertices(F, n);
  p.unreferenced = static_cast<int>(std::count(used.begin(), used.end(), false));
  p.uniform_rows = s.uniform_rows;
  p.solver = s.solver;
  return p;
}

Eigen::MatrixX3d minimal_surface(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights,
                                 int iterations, numerics::FixedBoundarySolve* last) {
  if (F.rows() == 0) throw Error("the mesh has no faces");
  const auto loops = numerics::boundary_loops(F);
  if (loops.empty()) throw Error("the mesh is closed (no boundary loop): a minimal surface needs a boundary to span");
  std::vector<int> fixed;
  for (const auto& loop : loops) fixed.insert(fixed.end(), loop.begin(), loop.end());
  Eigen::MatrixXd X = V;
  const int rounds = weights == Weights::uniform ? 1 : std::max(iterations, 1);
  for (int r = 0; r < rounds; ++r) {
    numerics::FixedBoundarySolve s = numerics::solve_fixed_boundary(weight_matrix(X, F, weights), F, fixed, X);
    X = std::move(s.X);
    if (last) *last = std::move(s);
  }
  return X;
}

}  // namespace loom::parameterize
