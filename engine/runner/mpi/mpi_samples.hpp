// A node split by samples over MPI ranks (--mpi-split samples), seen apart
// from MPI: which rank takes which sample, and what each rank did.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace loom::runner {

// Static: rank r takes the samples s % N == r. Dealt by speed (--mpi-deal
// dynamic): a table of W slots (PixelRegion::slots), rank r owning a run of
// slots in proportion to its speed, samples taken per busy second in the
// last pass in which it took any, and at least one slot (its speed is then
// measured again); every rank starts with an even share. After each pass,
// every rank calls passed() with every rank's figures for that pass, so
// that every rank holds the very same table. The speed in one pass deals the
// next: with a rank at half speed of three, a first even pass of 1/16 of the
// work alone costs (1/16)(2/3 − 0.4) / 0.4 = 4 % over the ideal (measured in
// all: 1.19x, docs/farm.md, "A slow rank").
class SampleDealing {
 public:
  SampleDealing(int ranks, bool by_speed);
  // Null when static.
  std::shared_ptr<const std::vector<int>> slots() const { return slots_; }
  // One pass summed over the ranks: rank r took taken[r] samples in busy[r]
  // seconds of its own work (its wait for the others not counted).
  void passed(const std::vector<double>& taken, const std::vector<double>& busy);
  // Rank 0's line after the node, `seconds` its time from its first pass to
  // the end of its last sum.
  std::string report(const std::string& node, double seconds) const;

 private:
  void deal();

  int ranks_;
  std::shared_ptr<std::vector<int>> slots_;  // dealt by speed: the rank owning each slot
  std::vector<double> speed_;                // samples per second, each rank's last measure
  std::vector<double> taken_, busy_;         // each rank's totals over the passes so far
  int passes_ = 0;
};

}  // namespace loom::runner
