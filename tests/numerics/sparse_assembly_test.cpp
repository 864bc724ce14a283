// sparse_from_triplets against Eigen's setFromTriplets (the reference: the
// same matrix, duplicates summed in the same order, so equal bit for bit),
// and its check: called during a large assembly, and able to stop it.
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "loom/numerics/sparse_assembly.hpp"

namespace loom::numerics {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// `count` triplets in a rows x cols matrix, many of them on the same entries
// (a small range of rows per column), in random order.
Triplets random_triplets(int rows, int cols, std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> col(0, cols - 1), near(0, 7);
  std::uniform_real_distribution<double> value(-1, 1);
  Triplets t;
  t.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    const int j = col(rng);
    t.emplace_back((j * 13 + near(rng)) % rows, j, value(rng));
  }
  return t;
}

SparseMatrix reference(int rows, int cols, const Triplets& t) {
  SparseMatrix A(rows, cols);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

void expect_identical(const SparseMatrix& a, const SparseMatrix& b) {
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  ASSERT_EQ(a.nonZeros(), b.nonZeros());
  ASSERT_TRUE(a.isCompressed());
  for (Eigen::Index j = 0; j <= a.cols(); ++j) ASSERT_EQ(a.outerIndexPtr()[j], b.outerIndexPtr()[j]) << j;
  for (Eigen::Index k = 0; k < a.nonZeros(); ++k) {
    ASSERT_EQ(a.innerIndexPtr()[k], b.innerIndexPtr()[k]) << k;
    ASSERT_EQ(a.valuePtr()[k], b.valuePtr()[k]) << k;  // the same sums, in the same order
  }
}

TEST(SparseAssembly, EqualsSetFromTripletsBitForBit) {
  for (const auto& [rows, cols] : {std::pair{50, 50}, std::pair{200, 30}, std::pair{7, 300}}) {
    const Triplets t = random_triplets(rows, cols, 5000, static_cast<unsigned>(rows + cols));
    expect_identical(sparse_from_triplets(rows, cols, t), reference(rows, cols, t));
  }
}

TEST(SparseAssembly, EmptyAndEmptyColumns) {
  expect_identical(sparse_from_triplets(4, 3, {}), reference(4, 3, {}));
  const Triplets t = {{3, 2, 1.5}, {0, 2, -1}, {3, 2, 0.25}};  // columns 0 and 1 empty
  expect_identical(sparse_from_triplets(4, 3, t), reference(4, 3, t));
}

TEST(SparseAssembly, ChecksDuringALargeAssemblyAndStopsWhenTheCheckThrows) {
  const Triplets t = random_triplets(100000, 100000, std::size_t(3) << 20, 1);
  int calls = 0;
  const SparseMatrix A = sparse_from_triplets(100000, 100000, t, [&] { ++calls; });
  EXPECT_GE(calls, 6);  // count and scatter passes: one per 2^20 triplets each
  expect_identical(A, reference(100000, 100000, t));
  int before_stop = 0;
  EXPECT_THROW(sparse_from_triplets(100000, 100000, t,
                                    [&] {
                                      if (++before_stop == 3) throw std::runtime_error("stop");
                                    }),
               std::runtime_error);
  EXPECT_EQ(before_stop, 3);
}

}  // namespace
}  // namespace loom::numerics
