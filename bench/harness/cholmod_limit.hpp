// The direct solvers' limit: what CHOLMOD itself needs for a matrix, with each
// fill-reducing ordering it offers, timed apart from any Loom code (no
// assembly, no copies): the symbolic analysis, the numeric factorization
// alone, and one solve. README's benchmark table divides these by Loom's
// time for the same matrix.
#pragma once

#include <string>
#include <vector>

#include <Eigen/SparseCore>

namespace loom::bench {

struct CholmodTiming {
  std::string ordering;  // "amd", "metis", "nesdis", or "default" (CHOLMOD's own choice, Loom's setting)
  int blas_threads = 1;  // OpenBLAS threads during the factorization (Loom uses 1: architecture.md, 16)
  double analyze = 0, factor = 0, solve = 0;  // median seconds
  double factor_nonzeros = 0, flops = 0;      // nnz(L) and the factorization's flop count
};

// A: symmetric positive definite, both triangles or the lower one (only the
// lower is read); rhs_columns: right-hand sides per solve; runs: timed runs
// (medians). Supernodal, as numerics::SparseCholesky. Each ordering is timed
// with OpenBLAS on one thread (as Loom runs it) and on every core, so that the
// limit is the best this machine's CHOLMOD can do, not only Loom's setting;
// BLAS is left on one thread afterwards.
std::vector<CholmodTiming> cholmod_orderings(const Eigen::SparseMatrix<double>& A, int rhs_columns, int runs);

// The fastest factorization over the orderings (analysis not counted).
const CholmodTiming& best_factor(const std::vector<CholmodTiming>& timings);

}  // namespace loom::bench
