#include "mpi/mpi_samples.hpp"

#include <algorithm>
#include <cstdio>

namespace loom::runner {
namespace {

// Slots in a pass: at least 16 a rank, so that the last slot of the slowest
// rank is a small part of its share (256 on up to 16 ranks).
int slot_count(int ranks) { return std::max(256, 16 * ranks); }

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

SampleShares::SampleShares(int ranks, bool dealt)
    : ranks_(ranks),
      slots_(dealt ? slot_count(ranks) : 0),
      taken_(std::size_t(ranks), 0),
      busy_(std::size_t(ranks), 0) {}

int SampleShares::slot(long fetched) const {
  const long slot = fetched - base_;
  return slot >= 0 && slot < slots_ ? int(slot) : -1;
}

void SampleShares::passed(const std::vector<double>& taken, const std::vector<double>& busy,
                          const std::vector<double>& next) {
  for (std::size_t r = 0; r < std::size_t(ranks_); ++r) {
    taken_[r] += taken[r];
    busy_[r] += busy[r];
    base_ = std::max(base_, long(next[r]));  // the counter's value: the last number fetched, plus one
  }
  ++passes_;
}

std::string SampleShares::report(const std::string& node, double seconds) const {
  char total[32];
  std::snprintf(total, sizeof total, "%.3f", seconds);
  return "mpi: " + node + ": samples " + (slots_ ? "dealt as ranks asked" : "taken") + " in " +
         std::to_string(passes_) + (passes_ == 1 ? " pass: " : " passes: ") + joined(taken_, "%.0f") + " to ranks 0.." +
         std::to_string(ranks_ - 1) + " (busy " + joined(busy_, "%.3f") + " s of " + total + " s)\n";
}

}  // namespace loom::runner
