#include "loom/numerics/fixed_boundary.hpp"

#include <algorithm>
#include <functional>
#include <numeric>

#include "loom/error.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "loom/numerics/sparse_solver.hpp"

namespace loom::numerics {

namespace {

// Every connected piece of F must touch a fixed vertex, or its rows are singular.
void require_fixed_in_every_piece(const Eigen::MatrixX3i& F, int n, const std::vector<char>& fixed) {
  int pieces = 0;
  const std::vector<int> piece_of = connected_components(F, n, &pieces);
  std::vector<char> anchored(static_cast<std::size_t>(pieces), 0);
  for (int v = 0; v < n; ++v)
    if (fixed[v] && piece_of[static_cast<std::size_t>(v)] >= 0) anchored[static_cast<std::size_t>(piece_of[static_cast<std::size_t>(v)])] = 1;
  int floating = 0;
  for (char a : anchored) floating += !a;
  if (floating > 0)
    throw Error("the mesh has " + std::to_string(floating) +
                " connected piece(s) without a boundary vertex: a fixed-boundary map needs one disk; "
                "split the mesh and map each piece");
}

}  // namespace

FixedBoundarySystem fixed_boundary_system(const SparseMatrix& W, const Eigen::MatrixX3i& F,
                                          const std::vector<int>& fixed, const Eigen::MatrixXd& X0,
                                          const std::function<void()>& check) {
  const int n = static_cast<int>(W.rows()), k = static_cast<int>(X0.cols());
  std::vector<char> is_fixed(n, 0);
  for (int v : fixed) is_fixed[v] = 1;
  require_fixed_in_every_piece(F, n, is_fixed);
  const std::vector<bool> used = referenced_vertices(F, n);
  FixedBoundarySystem sys;
  sys.index.assign(n, -1);
  int m = 0;
  for (int v = 0; v < n; ++v)
    if (used[v] && !is_fixed[v]) sys.index[v] = m++;
  sys.B = Eigen::MatrixXd::Zero(m, k);
  if (m == 0) return sys;
  const Eigen::SparseMatrix<double, Eigen::RowMajor> R = W;
  const double mean = R.cwiseAbs().sum() / std::max<Eigen::Index>(R.nonZeros(), 1);
  std::vector<std::vector<int>> adjacency;  // built only if a row needs the fallback
  // A is built row by row in compressed row-major form: rows follow the free
  // vertices in order and index[] is increasing, so each row's columns come
  // out sorted and no triplet sort is needed.
  std::vector<int> outer{0}, inner;
  std::vector<double> value;
  inner.reserve(static_cast<std::size_t>(R.nonZeros() + m));
  value.reserve(inner.capacity());
  for (int v = 0; v < n; ++v) {
    if (check && v % 65536 == 0) check();
    const int i = sys.index[v];
    if (i < 0) continue;
    double sum = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(R, v); it; ++it)
      if (it.col() != v) sum += it.value();
    bool diagonal_placed = false;
    auto add = [&](int u, double w) {
      if (u == v) return;
      sys.positive &= w >= 0;
      const int j = sys.index[u];
      if (j < 0) {
        sys.B.row(i) += w * X0.row(u);
        return;
      }
      if (!diagonal_placed && j > i) {
        inner.push_back(i), value.push_back(sum);
        diagonal_placed = true;
      }
      inner.push_back(j), value.push_back(-w);
    };
    if (sum > 1e-12 * mean) {
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(R, v); it; ++it)
        add(static_cast<int>(it.col()), it.value());
    } else {
      // Degenerate neighbourhood (zero-area faces): the uniform row keeps the
      // system regular.
      if (adjacency.empty()) adjacency = vertex_adjacency(F, n);
      sum = static_cast<double>(adjacency[v].size());
      for (int u : adjacency[v]) add(u, 1.0);
      ++sys.uniform_rows;
    }
    if (!diagonal_placed) inner.push_back(i), value.push_back(sum);
    outer.push_back(static_cast<int>(inner.size()));
  }
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> A_rows(
      m, m, static_cast<Eigen::Index>(inner.size()), outer.data(), inner.data(), value.data());
  sys.A = A_rows;
  // A is symmetric exactly when its column-major storage repeats its
  // row-major one (column i of A is then row i).
  const double tolerance = 1e-12 * Eigen::Map<const Eigen::VectorXd>(value.data(), Eigen::Index(value.size())).norm();
  sys.symmetric = sys.uniform_rows == 0 &&
                  std::equal(outer.begin(), outer.end(), sys.A.outerIndexPtr()) &&
                  std::equal(inner.begin(), inner.end(), sys.A.innerIndexPtr()) &&
                  (Eigen::Map<const Eigen::VectorXd>(value.data(), Eigen::Index(value.size())) -
                   Eigen::Map<const Eigen::VectorXd>(sys.A.valuePtr(), sys.A.nonZeros()))
                          .norm() <= tolerance;
  return sys;
}

FixedBoundarySolve solve_fixed_boundary(const SparseMatrix& W, const Eigen::MatrixX3i& F,
                                        const std::vector<int>& fixed, const Eigen::MatrixXd& X0,
                                        const std::function<void()>& check) {
  auto checkpoint = [&check] {
    if (check) check();
  };
  const FixedBoundarySystem sys = fixed_boundary_system(W, F, fixed, X0, check);
  FixedBoundarySolve result;
  result.X = X0;
  result.uniform_rows = sys.uniform_rows;
  if (sys.A.rows() == 0) return result;
  const SparseMatrix& A = sys.A;
  const Eigen::MatrixXd& B = sys.B;
  const bool positive = sys.positive;
  checkpoint();

  Eigen::MatrixXd Y;
  const bool symmetric = sys.symmetric;
  bool solved = false;
  if (symmetric) {
    // Negative cotangent weights can make A indefinite: LU still solves it.
    // The cancellation check stays outside the try blocks (Cancelled is an Error).
    SparseCholesky chol;
    bool factored = false;
    try {
      chol.compute(A, check);  // checks between CHOLMOD's analysis and factorization
      factored = true;
    } catch (const Cancelled&) {
      throw;
    } catch (const Error&) {
    }
    checkpoint();
    if (factored) {
      try {
        Y = chol.solve(B);
        result.solver = chol.backend();
        solved = true;
      } catch (const Error&) {
      }
    }
  }
  if (!solved) {
    // With positive weights A is row diagonally dominant with a non-positive
    // off-diagonal (an M-matrix): its LU needs no iterative refinement, which
    // would cost more than the triangular solves themselves.
    SparseLU lu(SparseLU::Options{positive ? 0 : 2});
    lu.compute(A, check);  // checks between UMFPACK's symbolic and numeric steps
    checkpoint();
    Y = lu.solve(B);
    result.solver = lu.backend();
  }
  if (!Y.allFinite()) throw Error("the linear system is singular: the mesh has degenerate faces everywhere");
  for (std::size_t v = 0; v < sys.index.size(); ++v)
    if (sys.index[v] >= 0) result.X.row(static_cast<Eigen::Index>(v)) = Y.row(sys.index[v]);
  return result;
}

}  // namespace loom::numerics
