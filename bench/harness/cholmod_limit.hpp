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
  double analyze = 0, factor = 0, solve = 0;  // median seconds
  double factor_nonzeros = 0, flops = 0;      // nnz(L) and the factorization's flop count
};

// A: symmetric positive definite, both triangles or the lower one (only the
// lower is read); rhs_columns: right-hand sides per solve; runs: timed runs
// (medians). Supernodal, as numerics::SparseCholesky.
std::vector<CholmodTiming> cholmod_orderings(const Eigen::SparseMatrix<double>& A, int rhs_columns, int runs);

// The fastest factorization over the orderings (analysis not counted).
const CholmodTiming& best_factor(const std::vector<CholmodTiming>& timings);

}  // namespace loom::bench
