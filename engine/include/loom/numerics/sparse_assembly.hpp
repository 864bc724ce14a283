// A sparse matrix from (row, column, value) triplets, in passes that call a
// check between chunks, so a node can stop during the assembly of a large
// system (Eigen's setFromTriplets is one uninterruptible call, over the 46M
// triplets of ARAP's ASAP start at 640k vertices).
//
//   triplets  any order; duplicates are summed in the order given, as
//             setFromTriplets sums them, so the result is the same bit for bit
//   check     called every ~1M triplets or columns (may throw to stop); empty: none
//   returns   rows by cols, column-major, compressed
#pragma once

#include <functional>
#include <vector>

#include <Eigen/SparseCore>

#include "loom/export.hpp"
#include "loom/numerics/sparse_solver.hpp"

namespace loom::numerics {

LOOM_API SparseMatrix sparse_from_triplets(Eigen::Index rows, Eigen::Index cols,
                                           const std::vector<Eigen::Triplet<double>>& triplets,
                                           const std::function<void()>& check = {});

}  // namespace loom::numerics
