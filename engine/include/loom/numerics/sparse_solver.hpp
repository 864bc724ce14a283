// Plugin author API. Sparse direct solves, in one place for every plugin.
//
// SparseCholesky: symmetric positive definite systems through CHOLMOD
// (supernodal, BLAS from OpenBLAS; SuiteSparse is a required dependency).
// Factor once, solve many right-hand sides: the symbolic analysis is kept so a
// matrix with the same pattern refactors fast. A is read in place (no copy).
// SparseLU: general square systems (e.g. mean-value weights, which are not
// symmetric) through UMFPACK. By default solve() applies UMFPACK's iterative
// refinement (up to 2 steps, each a residual, a backward-error estimate and
// another solve). Options::refinement_steps = 0 skips it: a solve is then
// just the triangular solves (about 3 times faster on mesh Laplacians), at
// the accuracy of the factorization, which is enough for well-conditioned
// systems such as diagonally dominant M-matrices (positive weights).
//
//   A  n by n sparse matrix (for Cholesky: both triangles or the lower one;
//      only the lower triangle is read)
//   B  n by k right-hand sides; returns X n by k with A X = B
//
// Errors (loom::Error): A not square, empty, with NaN/Inf entries, not positive
// definite (Cholesky) or singular (LU); solve() before a successful compute()
// or with a B of the wrong height. solve() is const and may be called from
// several threads at once on one object (each call has its own workspace);
// compute()/refactor() must not run concurrently with anything else on it.
#pragma once

#include <functional>
#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "loom/export.hpp"

namespace loom::numerics {

using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major

class LOOM_API SparseCholesky {
 public:
  struct Options {
    // Many solves for each factorization (a local/global solver's fixed
    // matrix): the factor is kept in CHOLMOD's simplicial form after the
    // supernodal factorization, whose triangular solves call no BLAS. For a
    // few right-hand-side columns the supernodal solve's BLAS calls, each
    // packing its small blocks, cost more than the arithmetic: the cloth
    // curtain's (81², 3 columns) local/global iteration took 2.0 ms with the
    // supernodal solve and 1.6 ms with this (docs/cloth.md). refactor() then
    // analyses again.
    bool simplicial_solves = false;
  };
  SparseCholesky();
  explicit SparseCholesky(const Options& options);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  // Throws loom::Error if A is not square or not positive definite
  // ("matrix is not positive definite (pivot k)"), never returns garbage.
  // `check` (optional, may throw to stop) is called between the symbolic
  // analysis and the numeric factorization: a node's cancellation check, since
  // neither CHOLMOD call can be interrupted (docs/robustness.md has their times).
  void compute(const SparseMatrix& A, const std::function<void()>& check = {});
  // Same pattern as the last compute(): reuses the symbolic analysis (the
  // fill-reducing ordering and supernodes) and redoes only the numeric part.
  // A different pattern, or no earlier compute(), falls back to compute().
  void refactor(const SparseMatrix& A, const std::function<void()>& check = {});
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  int rows() const;
  const char* backend() const;  // "cholmod"

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class LOOM_API SparseLU {
 public:
  struct Options {
    int refinement_steps = 2;  // UMFPACK_IRSTEP: >= 0, 0 = none
  };
  SparseLU();
  explicit SparseLU(const Options& options);  // throws loom::Error for refinement_steps < 0
  ~SparseLU();
  SparseLU(SparseLU&&) noexcept;
  SparseLU& operator=(SparseLU&&) noexcept;

  // Throws loom::Error if singular; `check` as for SparseCholesky::compute,
  // between UMFPACK's symbolic and numeric factorizations.
  void compute(const SparseMatrix& A, const std::function<void()>& check = {});
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  const char* backend() const;  // "umfpack"

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace loom::numerics
