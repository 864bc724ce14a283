// Walker's alias method (Vose 1991's construction): sampling a discrete
// distribution in O(1) with one uniform number. Used for power-weighted light
// selection and for the environment map's pixels.
#pragma once

#include <cstdint>
#include <vector>

namespace loom::pathtrace {

class AliasTable {
 public:
  AliasTable() = default;
  // Non-negative weights; all zero (or empty) gives an empty table.
  explicit AliasTable(const std::vector<double>& weights);

  bool empty() const { return bins_.empty(); }
  std::size_t size() const { return bins_.size(); }
  // An index with probability weight[i] / sum, from u in [0, 1).
  std::uint32_t sample(float u) const {
    const float scaled = u * float(bins_.size());
    const std::uint32_t last = std::uint32_t(bins_.size() - 1);
    std::uint32_t i = std::uint32_t(scaled);
    if (i > last) i = last;
    float up = scaled - float(i);
    if (!(up < 0x1.fffffep-1f)) up = 0x1.fffffep-1f;  // below 1 (not fmin: a libm call)
    return up < bins_[i].q ? i : bins_[i].alias;
  }
  float pmf(std::size_t i) const { return bins_[i].p; }
  double total() const { return total_; }

 private:
  struct Bin {
    float q = 0;          // probability of keeping this bin rather than its alias
    float p = 0;          // the bin's own probability
    std::uint32_t alias = 0;
  };
  std::vector<Bin> bins_;
  double total_ = 0;
};

}  // namespace loom::pathtrace
