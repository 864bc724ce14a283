#include "mpi/mpi_samples.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>

namespace loom::runner {
namespace {

// Slots in the table: a share is dealt in steps of 1/256 (at least 4 a rank).
int slot_count(int ranks) { return std::max(256, 4 * ranks); }

std::string joined(const std::vector<double>& values, const char* format) {
  std::string text;
  for (double v : values) {
    char one[32];
    std::snprintf(one, sizeof one, format, v);
    text += (text.empty() ? "" : ", ") + std::string(one);
  }
  return text;
}

}  // namespace

SampleDealing::SampleDealing(int ranks, bool by_speed)
    : ranks_(ranks), speed_(std::size_t(ranks), 1.0), taken_(std::size_t(ranks), 0), busy_(std::size_t(ranks), 0) {
  if (!by_speed) return;
  slots_ = std::make_shared<std::vector<int>>(std::size_t(slot_count(ranks)));
  deal();
}

void SampleDealing::passed(const std::vector<double>& taken, const std::vector<double>& busy) {
  for (std::size_t r = 0; r < std::size_t(ranks_); ++r) {
    taken_[r] += taken[r];
    busy_[r] += busy[r];
    if (taken[r] > 0 && busy[r] > 0) speed_[r] = taken[r] / busy[r];
  }
  ++passes_;
  if (slots_) deal();
}

// One slot to every rank, then the others in proportion to the speeds, by
// largest remainder (Hamilton's method), the table in runs: rank 0's slots
// first. The same doubles on every rank give the same table.
void SampleDealing::deal() {
  const int free = int(slots_->size()) - ranks_;
  const double total = std::accumulate(speed_.begin(), speed_.end(), 0.0);
  std::vector<int> owned(std::size_t(ranks_), 1);
  std::vector<std::pair<double, int>> remainder;
  int dealt = 0;
  for (int r = 0; r < ranks_; ++r) {
    const double quota = free * speed_[std::size_t(r)] / total;
    owned[std::size_t(r)] += int(quota);
    dealt += int(quota);
    remainder.emplace_back(quota - int(quota), r);
  }
  std::sort(remainder.begin(), remainder.end(),
            [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
  for (int i = 0; i < free - dealt; ++i) ++owned[std::size_t(remainder[std::size_t(i)].second)];
  auto slot = slots_->begin();
  for (int r = 0; r < ranks_; ++r) slot = std::fill_n(slot, owned[std::size_t(r)], r);
}

std::string SampleDealing::report(const std::string& node, double seconds) const {
  char total[32];
  std::snprintf(total, sizeof total, "%.3f", seconds);
  return "mpi: " + node + ": samples " + (slots_ ? "dealt by speed" : "taken") + " in " + std::to_string(passes_) +
         (passes_ == 1 ? " pass: " : " passes: ") + joined(taken_, "%.0f") + " to ranks 0.." +
         std::to_string(ranks_ - 1) + " (busy " + joined(busy_, "%.3f") + " s of " + total + " s)\n";
}

}  // namespace loom::runner
