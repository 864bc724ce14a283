// Sparse direct solves, in one place for every plugin.
//
// SparseCholesky: symmetric positive (semi-)definite systems through CHOLMOD
// (supernodal, BLAS from OpenBLAS), with Eigen's SimplicialLDLT as a fallback
// when CHOLMOD is not built in. Factor once, solve many right-hand sides: the
// symbolic analysis is kept so a matrix with the same pattern refactors fast.
// SparseLU: general square systems (e.g. mean-value weights, which are not
// symmetric) through UMFPACK, Eigen's SparseLU as fallback.
//
//   A  n by n sparse matrix (for Cholesky: both triangles or the lower one)
//   B  n by k right-hand sides; returns X n by k with A X = B
#pragma once

#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "loom/export.hpp"

namespace loom::numerics {

using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major

class LOOM_API SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  // Throws loom::Error if A is not square or not positive definite
  // ("matrix is not positive definite (pivot k)"), never returns garbage.
  void compute(const SparseMatrix& A);
  // Same pattern as the last compute(): reuses the symbolic analysis.
  void refactor(const SparseMatrix& A);
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  int rows() const;
  const char* backend() const;  // "cholmod" or "eigen"

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class LOOM_API SparseLU {
 public:
  SparseLU();
  ~SparseLU();
  SparseLU(SparseLU&&) noexcept;
  SparseLU& operator=(SparseLU&&) noexcept;

  void compute(const SparseMatrix& A);  // throws loom::Error if singular
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  const char* backend() const;  // "umfpack" or "eigen"

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace loom::numerics
