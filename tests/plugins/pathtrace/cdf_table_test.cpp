// Light selection by inverse CDF (cdf_table.hpp): each index drawn with
// probability weight / sum (chi-square), never one of weight 0, and the
// remainder it returns is uniform on [0, 1) given the index (chi-square per
// index), so reusing it for the point on the light stays unbiased.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "cdf_table.hpp"
#include "test_scenes.hpp"

namespace {

using loom::pathtrace::CdfTable;

TEST(CdfTable, FrequenciesMatchTheWeightsAndTheRemainderIsUniform) {
  const std::vector<double> w = {1, 2, 0, 7, 0.5, 30, 0, 3, 1e-3, 4, 0};
  const CdfTable table(w);
  double sum = 0;
  for (double x : w) sum += x;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uni(0, 1);
  const int n = 2000000, bins = 10;
  std::vector<int> count(w.size(), 0);
  std::vector<std::vector<int>> rest(w.size(), std::vector<int>(bins, 0));
  for (int i = 0; i < n; ++i) {
    const CdfTable::Choice c = table.sample(uni(rng));
    ASSERT_LT(c.index, w.size());
    ASSERT_GE(c.remainder, 0.f);
    ASSERT_LT(c.remainder, 1.f);
    ++count[c.index];
    ++rest[c.index][int(c.remainder * bins)];
  }
  for (std::size_t i = 0; i < w.size(); ++i) {
    EXPECT_NEAR(table.pmf(i), w[i] / sum, 1e-7);
    if (count[i] < 10000) continue;
    const double expected = count[i] / double(bins);
    double chi2_rest = 0;
    for (int r : rest[i]) chi2_rest += (r - expected) * (r - expected) / expected;
    EXPECT_LT(chi2_rest, 27.9) << "index " << i;  // 99.9 % quantile, 9 dof
  }
  const auto chi2 = loom::pathtrace::test::chi_square_against_weights(w, count, n);
  EXPECT_EQ(chi2.dof, 7);
  EXPECT_LT(chi2.value, 24.3);  // 99.9 % quantile, 7 dof
}

TEST(CdfTable, MonotoneInU) {
  const CdfTable table(std::vector<double>{3, 0, 1, 2});
  std::uint32_t previous = 0;
  for (int k = 0; k < 1000; ++k) {
    const CdfTable::Choice c = table.sample(float(k) / 1000);
    EXPECT_GE(c.index, previous);
    EXPECT_NE(c.index, 1u);
    previous = c.index;
  }
  EXPECT_EQ(table.sample(0.99999994f).index, 3u);
}

TEST(CdfTable, EmptyAndDegenerateWeights) {
  EXPECT_TRUE(CdfTable(std::vector<double>{}).empty());
  EXPECT_TRUE(CdfTable(std::vector<double>{0, 0, 0}).empty());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const CdfTable t(std::vector<double>{nan, 1, -3, std::numeric_limits<double>::infinity()});
  ASSERT_FALSE(t.empty());
  for (float u : {0.f, 0.3f, 0.6f, 0.99999994f}) EXPECT_EQ(t.sample(u).index, 1u);
}

}  // namespace
