#include "harmonic_map.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "loom/error.hpp"
#include "loom/numerics/laplacian.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "loom/numerics/sparse_solver.hpp"

namespace loom::parameterize {

const std::vector<std::string> weight_names = {"uniform",           "cotangent",  "cotangent_clamped",
                                               "intrinsic_delaunay", "mean_value", "shape_preserving"};

Weights parse_weights(const std::string& name) {
  for (size_t k = 0; k < weight_names.size(); ++k)
    if (weight_names[k] == name) return static_cast<Weights>(k);
  throw Error("unknown weights \"" + name + "\"");
}

SparseMatrix weight_matrix(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights) {
  switch (weights) {
    case Weights::uniform: return numerics::uniform_weights(F, static_cast<int>(V.rows()));
    case Weights::cotangent: return numerics::cotangent_weights(V, F);
    case Weights::cotangent_clamped: {
      // Clamping at a small fraction of the mean magnitude keeps every weight
      // positive (Floater 2003, Tutte's theorem: the map cannot fold) while
      // changing only the obtuse-dominated edges.
      SparseMatrix W = numerics::cotangent_weights(V, F);
      const double floor = 1e-3 * W.cwiseAbs().sum() / std::max<Eigen::Index>(W.nonZeros(), 1);
      for (Eigen::Index k = 0; k < W.nonZeros(); ++k) W.valuePtr()[k] = std::max(W.valuePtr()[k], floor);
      return W;
    }
    case Weights::intrinsic_delaunay: return numerics::intrinsic_delaunay_cotangent_weights(V, F);
    case Weights::mean_value: return numerics::mean_value_weights(V, F);
    case Weights::shape_preserving: return shape_preserving_weights(V, F);
  }
  throw Error("unknown weights");
}

namespace {

int find(std::vector<int>& parent, int v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

// Every connected piece of F must touch a fixed vertex, or its rows are singular.
void require_fixed_in_every_piece(const Eigen::MatrixX3i& F, int n, const std::vector<char>& fixed) {
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 1; k < 3; ++k) parent[find(parent, F(f, k))] = find(parent, F(f, 0));
  std::vector<char> anchored(n, 0), piece(n, 0);
  for (int v = 0; v < n; ++v)
    if (fixed[v]) anchored[find(parent, v)] = 1;
  int floating = 0;
  for (int f = 0; f < F.rows(); ++f) {
    const int r = find(parent, F(f, 0));
    if (!anchored[r] && !piece[r]) {
      piece[r] = 1;
      ++floating;
    }
  }
  if (floating > 0)
    throw Error("the mesh has " + std::to_string(floating) +
                " connected piece(s) without a boundary vertex: a fixed-boundary map needs one disk; "
                "split the mesh and map each piece");
}

}  // namespace

FixedBoundarySolve solve_fixed_boundary(const SparseMatrix& W, const Eigen::MatrixX3i& F,
                                        const std::vector<int>& fixed, const Eigen::MatrixXd& X0) {
  const int n = static_cast<int>(W.rows()), k = static_cast<int>(X0.cols());
  std::vector<char> is_fixed(n, 0);
  for (int v : fixed) is_fixed[v] = 1;
  require_fixed_in_every_piece(F, n, is_fixed);
  const std::vector<bool> used = numerics::referenced_vertices(F, n);
  std::vector<int> index(n, -1);
  int m = 0;
  for (int v = 0; v < n; ++v)
    if (used[v] && !is_fixed[v]) index[v] = m++;

  FixedBoundarySolve result;
  result.X = X0;
  if (m == 0) return result;
  const Eigen::SparseMatrix<double, Eigen::RowMajor> R = W;
  const double mean = R.cwiseAbs().sum() / std::max<Eigen::Index>(R.nonZeros(), 1);
  bool positive = true;                     // every weight used >= 0: A is an M-matrix
  std::vector<std::vector<int>> adjacency;  // built only if a row needs the fallback
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(R.nonZeros() + m);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(m, k);
  for (int v = 0; v < n; ++v) {
    const int i = index[v];
    if (i < 0) continue;
    double sum = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(R, v); it; ++it)
      if (it.col() != v) sum += it.value();
    auto add = [&](int u, double w) {
      if (u == v) return;
      positive &= w >= 0;
      if (index[u] >= 0) t.emplace_back(i, index[u], -w);
      else B.row(i) += w * X0.row(u);
    };
    if (sum > 1e-12 * mean) {
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(R, v); it; ++it)
        add(static_cast<int>(it.col()), it.value());
    } else {
      // Degenerate neighbourhood (zero-area faces): the uniform row keeps the
      // system regular.
      if (adjacency.empty()) adjacency = numerics::vertex_adjacency(F, n);
      for (int u : adjacency[v]) add(u, 1.0);
      sum = static_cast<double>(adjacency[v].size());
      ++result.uniform_rows;
    }
    t.emplace_back(i, i, sum);
  }
  SparseMatrix A(m, m);
  A.setFromTriplets(t.begin(), t.end());

  Eigen::MatrixXd Y;
  const bool symmetric = result.uniform_rows == 0 && (SparseMatrix(A.transpose()) - A).norm() <= 1e-12 * A.norm();
  bool solved = false;
  if (symmetric) {
    try {
      numerics::SparseCholesky chol;
      chol.compute(A);
      Y = chol.solve(B);
      result.solver = chol.backend();
      solved = true;
    } catch (const Error&) {
      // Negative cotangent weights can make A indefinite: LU still solves it.
    }
  }
  if (!solved) {
    // With positive weights A is row diagonally dominant with a non-positive
    // off-diagonal (an M-matrix): its LU needs no iterative refinement, which
    // would cost more than the triangular solves themselves.
    numerics::SparseLU lu(numerics::SparseLU::Options{positive ? 0 : 2});
    lu.compute(A);
    Y = lu.solve(B);
    result.solver = lu.backend();
  }
  if (!Y.allFinite()) throw Error("the linear system is singular: the mesh has degenerate faces everywhere");
  for (int v = 0; v < n; ++v)
    if (index[v] >= 0) result.X.row(v) = Y.row(index[v]);
  return result;
}

Parameterization parameterize(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights,
                              BoundaryShape shape) {
  if (F.rows() == 0) throw Error("the mesh has no faces");
  const int n = static_cast<int>(V.rows());
  const auto loops = numerics::boundary_loops(F);
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

  const Eigen::MatrixX2d boundary = map_boundary(V, F, loops[0], shape);
  Eigen::MatrixXd X0 = Eigen::MatrixXd::Zero(n + extra, 2);
  for (size_t k = 0; k < loops[0].size(); ++k) X0.row(loops[0][k]) = boundary.row(k);
  const FixedBoundarySolve s = solve_fixed_boundary(weight_matrix(V2, F2, weights), F2, loops[0], X0);

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
                                 int iterations, FixedBoundarySolve* last) {
  if (F.rows() == 0) throw Error("the mesh has no faces");
  const auto loops = numerics::boundary_loops(F);
  if (loops.empty()) throw Error("the mesh is closed (no boundary loop): a minimal surface needs a boundary to span");
  std::vector<int> fixed;
  for (const auto& loop : loops) fixed.insert(fixed.end(), loop.begin(), loop.end());
  Eigen::MatrixXd X = V;
  const int rounds = weights == Weights::uniform ? 1 : std::max(iterations, 1);
  for (int r = 0; r < rounds; ++r) {
    FixedBoundarySolve s = solve_fixed_boundary(weight_matrix(X, F, weights), F, fixed, X);
    X = std::move(s.X);
    if (last) *last = std::move(s);
  }
  return X;
}

}  // namespace loom::parameterize
