// The alias table draws each index with probability weight / sum (chi-square).
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "alias_table.hpp"
#include "test_scenes.hpp"

namespace {

using loom::pathtrace::AliasTable;

TEST(AliasTable, FrequenciesMatchTheWeights) {
  const std::vector<double> w = {1, 2, 0, 7, 0.5, 30, 0, 3, 1e-3, 4};
  const AliasTable table(w);
  double sum = 0;
  for (double x : w) sum += x;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uni(0, 1);
  const int n = 2000000;
  std::vector<int> count(w.size(), 0);
  for (int i = 0; i < n; ++i) ++count[table.sample(uni(rng))];
  for (std::size_t i = 0; i < w.size(); ++i) EXPECT_NEAR(table.pmf(i), w[i] / sum, 1e-7);
  const auto chi2 = loom::pathtrace::test::chi_square_against_weights(w, count, n);
  EXPECT_EQ(chi2.dof, 7);
  // 99.9% quantile of chi-square with 7 degrees of freedom: 24.3.
  EXPECT_LT(chi2.value, 24.3);
}

TEST(AliasTable, EmptyAndDegenerateWeights) {
  EXPECT_TRUE(AliasTable(std::vector<double>{}).empty());
  EXPECT_TRUE(AliasTable(std::vector<double>{0, 0, 0}).empty());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const AliasTable t(std::vector<double>{nan, 1, -3, std::numeric_limits<double>::infinity()});
  ASSERT_FALSE(t.empty());
  for (float u : {0.f, 0.3f, 0.6f, 0.99999994f}) EXPECT_EQ(t.sample(u), 1u);
}

}  // namespace
