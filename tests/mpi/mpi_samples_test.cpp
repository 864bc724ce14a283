// SampleShares (engine/runner/mpi/mpi_samples.hpp) without MPI: the slots of
// a pass dealt from a counter that is never reset, with ranks asking in any
// order, each pass's slots taken exactly once.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "mpi/mpi_samples.hpp"

namespace {

TEST(SampleShares, StaticHasNoSlots) { EXPECT_EQ(loom::runner::SampleShares(3, false).slots(), 0); }

TEST(SampleShares, AtLeastSixteenSlotsARank) {
  EXPECT_EQ(loom::runner::SampleShares(3, true).slots(), 256);
  EXPECT_EQ(loom::runner::SampleShares(100, true).slots(), 1600);
}

// Ranks ask a shared counter in a random order until each is told the pass
// is taken; a rank may sit a pass out (it asks nothing). Every pass's slots
// must each go to exactly one rank, and every rank that asks must be told
// once that the pass is taken.
TEST(SampleShares, EveryPassIsTakenOnceWhateverTheOrderOfAsks) {
  constexpr int kRanks = 3;
  std::vector<loom::runner::SampleShares> ranks(kRanks, loom::runner::SampleShares(kRanks, true));
  const int slots = ranks[0].slots();
  long counter = 0;  // rank 0's window
  std::mt19937 random(7);
  for (int pass = 0; pass < 6; ++pass) {
    std::vector<int> taken_by(std::size_t(slots), -1);
    std::vector<double> next(kRanks), none(kRanks, 0);
    std::vector<bool> done(kRanks, false);
    for (int r = 0; r < kRanks; ++r) next[std::size_t(r)] = double(ranks[std::size_t(r)].base());
    if (pass == 3) done[1] = true;  // rank 1 asks nothing this pass
    for (int left = kRanks - (pass == 3 ? 1 : 0); left > 0;) {
      const int r = int(random() % kRanks);
      if (done[std::size_t(r)]) continue;
      const long fetched = counter++;
      next[std::size_t(r)] = double(fetched + 1);
      const int slot = ranks[std::size_t(r)].slot(fetched);
      if (slot < 0) {
        done[std::size_t(r)] = true;
        --left;
        continue;
      }
      ASSERT_EQ(taken_by[std::size_t(slot)], -1) << "pass " << pass << " slot " << slot << " taken twice";
      taken_by[std::size_t(slot)] = r;
    }
    for (int s = 0; s < slots; ++s) EXPECT_GE(taken_by[std::size_t(s)], 0) << "pass " << pass << " slot " << s;
    for (auto& rank : ranks) rank.passed(none, none, next);
    for (auto& rank : ranks) EXPECT_EQ(rank.base(), counter);
  }
}

TEST(SampleShares, ReportsEachRanksSamplesAndBusyTime) {
  loom::runner::SampleShares shares(2, true);
  shares.passed({100, 50}, {1.0, 1.5}, {258, 258});
  shares.passed({10, 5}, {0.5, 0.25}, {516, 516});
  EXPECT_EQ(shares.report("trace", 2.5),
            "mpi: trace: samples dealt as ranks asked in 2 passes: 110, 55 to ranks 0..1 (busy 1.500, 1.750 s of "
            "2.500 s)\n");
}

}  // namespace
