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
  std::uint32_t sample(float u) const;
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
