// SampleDealing (engine/runner/mpi/mpi_samples.hpp) and PixelRegion::takes_sample
// with its table, without MPI: the table against Hamilton's apportionment
// worked by hand, and every sample of a pass taken by exactly one rank, the
// ranks' shares those of their slots.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "loom/node.hpp"
#include "mpi/mpi_samples.hpp"

namespace {

std::vector<int> slots_per_rank(const std::vector<int>& table, int ranks) {
  std::vector<int> owned(std::size_t(ranks), 0);
  for (int r : table) ++owned[std::size_t(r)];
  return owned;
}

TEST(SampleDealing, StaticHasNoTable) { EXPECT_EQ(loom::runner::SampleDealing(3, false).slots(), nullptr); }

TEST(SampleDealing, FirstPassIsEven) {
  const loom::runner::SampleDealing deal(3, true);
  // 256 slots: one each, then 253 by equal quotas of 84.33: 84 each, and the one left to
  // rank 0 (equal remainders go to the lower rank).
  EXPECT_EQ(slots_per_rank(*deal.slots(), 3), (std::vector<int>{86, 85, 85}));
}

TEST(SampleDealing, SlotsFollowSpeedsByLargestRemainder) {
  loom::runner::SampleDealing deal(3, true);
  deal.passed({1000, 1000, 250}, {1, 1, 0.5});  // speeds 1000, 1000, 500 samples a second
  // One slot each, then 253 x (2/5, 2/5, 1/5) = 101.2, 101.2, 50.6: 101, 101, 50 and the
  // one left to the largest remainder (rank 2's 0.6).
  const std::vector<int>& table = *deal.slots();
  EXPECT_EQ(slots_per_rank(table, 3), (std::vector<int>{102, 102, 52}));
  for (std::size_t i = 1; i < table.size(); ++i) EXPECT_LE(table[i - 1], table[i]);  // in runs, rank 0's first
}

TEST(SampleDealing, ARankThatTookNothingKeepsItsLastSpeedAndASlot) {
  loom::runner::SampleDealing deal(3, true);
  deal.passed({1000, 1000, 500}, {1, 1, 1});
  deal.passed({0, 1000, 1000}, {0.1, 1, 2});  // rank 0 took nothing: its speed stays 1000
  // Speeds 1000, 1000, 500 again: the same table.
  EXPECT_EQ(slots_per_rank(*deal.slots(), 3), (std::vector<int>{102, 102, 52}));
  deal.passed({0, 1e6, 1}, {1, 1, 1e6});  // rank 2 at a millionth of the others' speed
  EXPECT_GE(slots_per_rank(*deal.slots(), 3)[2], 1);
}

TEST(PixelRegion, EverySampleOfAPassGoesToOneRankInProportionToItsSlots) {
  loom::runner::SampleDealing deal(3, true);
  deal.passed({1000, 1000, 250}, {1, 1, 0.5});
  const std::vector<int> owned = slots_per_rank(*deal.slots(), 3);
  constexpr std::size_t kPixels = 65536;
  for (int samples : {1, 4, 64}) {  // passes of one sample a pixel are dealt as finely as long ones
    std::array<double, 3> taken{};
    for (std::size_t p = 0; p < kPixels; ++p)
      for (int s = 100; s < 100 + samples; ++s) {
        int takers = 0;
        for (int r = 0; r < 3; ++r) {
          const loom::PixelRegion region{32, r, 3, true, deal.slots()};
          if (region.takes_sample(p, s)) {
            ++takers;
            ++taken[std::size_t(r)];
          }
        }
        ASSERT_EQ(takers, 1) << "pixel " << p << " sample " << s;
      }
    for (int r = 0; r < 3; ++r)
      EXPECT_NEAR(taken[std::size_t(r)] / (double(kPixels) * samples), owned[std::size_t(r)] / 256.0, 0.01)
          << samples << " samples a pixel, rank " << r;
  }
}

}  // namespace
