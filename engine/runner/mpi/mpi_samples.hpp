// A node split by samples over MPI ranks (--mpi-split samples), seen apart
// from MPI: which slot of a pass a rank's ask stands for, and what each rank
// did.
#pragma once

#include <string>
#include <vector>

namespace loom::runner {

// Static: rank r takes the samples s % N == r of every pixel. Dealt as ranks
// ask (--mpi-deal dynamic): every pass is cut into slots()
// (PixelRegion::slots) and each rank takes the next slot from a counter on
// rank 0 as it finishes one, so a faster rank takes more slots. Numbers from
// the counter are never reset: pass k's slots are the numbers base_k ..
// base_k + slots() - 1, and every number past them tells the rank that asked
// that the pass is taken (one such ask per rank and pass). After each pass
// every rank calls passed() with every rank's figures, the counter's value
// among them, so every rank holds the same base for the next pass.
class SampleShares {
 public:
  SampleShares(int ranks, bool dealt);
  int slots() const { return slots_; }  // 0: static
  // The slot of the current pass that the counter's number `fetched` stands
  // for, or -1 when it is past the pass's last slot.
  int slot(long fetched) const;
  // The counter's number that the current pass's slots start at.
  long base() const { return base_; }
  int passes() const { return passes_; }  // summed so far
  // One pass summed over the ranks: rank r took taken[r] samples in busy[r]
  // seconds of its own work (its wait for the others not counted) and, dealt,
  // next[r] is one past the last number it fetched (base() if none).
  void passed(const std::vector<double>& taken, const std::vector<double>& busy, const std::vector<double>& next);
  // Rank 0's line after the node, `seconds` its time from its first pass to
  // the end of its last sum.
  std::string report(const std::string& node, double seconds) const;

 private:
  int ranks_, slots_;
  long base_ = 0;
  std::vector<double> taken_, busy_;  // each rank's totals over the passes so far
  int passes_ = 0;
};

}  // namespace loom::runner
