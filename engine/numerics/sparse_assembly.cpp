#include "loom/numerics/sparse_assembly.hpp"

#include <algorithm>
#include <cstddef>
#include <memory>

namespace loom::numerics {

namespace {

constexpr std::size_t kChunk = std::size_t(1) << 20;  // items between checks (a few ms each)

}  // namespace

// A bucket sort by column (counting, then scattering in the given order),
// then per column a stable sort by row and the sum of duplicates: the order
// in which setFromTriplets adds them.
SparseMatrix sparse_from_triplets(Eigen::Index rows, Eigen::Index cols,
                                  const std::vector<Eigen::Triplet<double>>& triplets,
                                  const std::function<void()>& check) {
  using Index = SparseMatrix::StorageIndex;
  auto every_chunk = [&](std::size_t k) {
    if (check && k % kChunk == 0) check();
  };
  std::vector<Index> start(static_cast<std::size_t>(cols) + 1, 0);
  for (std::size_t k = 0; k < triplets.size(); ++k) {
    every_chunk(k);
    ++start[static_cast<std::size_t>(triplets[k].col()) + 1];
  }
  for (Eigen::Index j = 0; j < cols; ++j) start[j + 1] += start[j];
  // Not value-initialized: zeroing hundreds of MB is an uninterruptible
  // memset, and the scatter below writes every entry.
  const std::unique_ptr<Index[]> row(new Index[triplets.size()]);
  const std::unique_ptr<double[]> value(new double[triplets.size()]);
  std::vector<Index> fill(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < triplets.size(); ++k) {
    every_chunk(k);
    const Index at = fill[triplets[k].col()]++;
    row[at] = triplets[k].row();
    value[at] = triplets[k].value();
  }
  // Per column: insertion sort by row (stable; columns are short), then the
  // duplicates summed and the column moved down to `kept`.
  Index kept = 0;
  std::vector<Index> outer(start.size(), 0);
  for (Eigen::Index j = 0; j < cols; ++j) {
    const Index begin = start[j], end = start[j + 1];
    if (check && begin / kChunk != end / kChunk) check();  // by entries: columns differ in length
    for (Index k = begin + 1; k < end; ++k)
      for (Index m = k; m > begin && row[m - 1] > row[m]; --m) std::swap(row[m - 1], row[m]), std::swap(value[m - 1], value[m]);
    outer[j] = kept;
    for (Index k = begin; k < end; ++k) {
      if (k > begin && row[k] == row[kept - 1]) {
        value[kept - 1] += value[k];
      } else {
        row[kept] = row[k], value[kept] = value[k];
        ++kept;
      }
    }
  }
  outer[cols] = kept;
  if (check) check();
  SparseMatrix A(rows, cols);
  A.resizeNonZeros(kept);
  std::copy(outer.begin(), outer.end(), A.outerIndexPtr());
  std::copy(row.get(), row.get() + kept, A.innerIndexPtr());
  std::copy(value.get(), value.get() + kept, A.valuePtr());
  return A;
}

}  // namespace loom::numerics
