// Plugin author API. Maps with fixed boundary values: every free vertex is the weighted average of
// its neighbours, Σ_j w_ij (x_j - x_i) = 0 (Tutte 1963; Floater 1997, 2003),
// one factorization for all k coordinates. Shared by the parameterize plugin
// (every weight and boundary) and the arap plugin (its Tutte start).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "loom/export.hpp"

namespace loom::numerics {

using SparseMatrix = Eigen::SparseMatrix<double>;

struct FixedBoundarySolve {
  Eigen::MatrixXd X;        // #V by k: given rows on fixed vertices, solved rows on free ones
  int uniform_rows = 0;     // free vertices whose weights summed to <= 0, solved with w_ij = 1
  std::string solver;       // "cholmod", "umfpack", ...
};

// The linear system of solve_fixed_boundary below, before it is solved:
// A Y = B with Y the free vertices' rows. A is an M-matrix when `positive`.
struct FixedBoundarySystem {
  SparseMatrix A;           // #free by #free, both triangles
  Eigen::MatrixXd B;        // #free by k: the fixed neighbours' share
  std::vector<int> index;   // #V: row of each free vertex in A, −1 for fixed or unreferenced
  bool positive = true;     // every weight used is >= 0
  bool symmetric = false;   // A = Aᵀ (to 1e-12) and no fallback rows: Cholesky applies
  int uniform_rows = 0;     // as FixedBoundarySolve::uniform_rows
};
// check as for solve_fixed_boundary, every 65536 rows.
LOOM_API FixedBoundarySystem fixed_boundary_system(const SparseMatrix& W, const Eigen::MatrixX3i& F,
                                                   const std::vector<int>& fixed, const Eigen::MatrixXd& X0,
                                                   const std::function<void()>& check = {});

// Solves Σ_j w_ij (x_j - x_i) = 0 for the free vertices: those referenced
// by F and not fixed. Rows of unreferenced vertices keep X0's values.
//   W      #V by #V weights, row i for vertex i (loom/numerics/laplacian.hpp)
//   F      #F by 3 (for the fallback rows and to find referenced vertices)
//   fixed  indices of fixed vertices
//   X0     #V by k: the fixed rows' values (other rows are ignored)
//   check  called between the long stages (assembly, factorization, solve);
//          a node passes [&ctx] { ctx.check_cancelled(); } so Ctrl-C acts
//          within one stage (its exception propagates unchanged)
// Throws loom::Error if a connected piece of the mesh has no fixed vertex.
LOOM_API FixedBoundarySolve solve_fixed_boundary(const SparseMatrix& W, const Eigen::MatrixX3i& F,
                                                 const std::vector<int>& fixed, const Eigen::MatrixXd& X0,
                                                 const std::function<void()>& check = {});

}  // namespace loom::numerics
