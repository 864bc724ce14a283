// Selection of a discrete outcome by inverting its cumulative distribution
// (binary search), returning the rest of the uniform number rescaled to
// [0, 1) so the chosen outcome can use it again: u in [F(i), F(i+1)) picks i,
// and (u - F(i)) / p_i is uniform on [0, 1) given i (pbrt-v4's
// SampleDiscrete; Cycles picks its lights this way). Light selection uses it
// so that one 2D low-discrepancy point covers all emitters' surfaces at once:
// neighbouring u pick neighbouring triangles of a mesh, and stratification
// in u carries over to the points on them.
#pragma once

#include <cstdint>
#include <vector>

namespace loom::pathtrace {

class CdfTable {
 public:
  CdfTable() = default;
  // Non-negative weights (negative, NaN and infinite count as 0); all zero
  // (or none) gives an empty table.
  explicit CdfTable(const std::vector<double>& weights);

  bool empty() const { return pmf_.empty(); }
  std::size_t size() const { return pmf_.size(); }
  float pmf(std::size_t i) const { return pmf_[i]; }

  struct Choice {
    std::uint32_t index;
    float remainder;  // in [0, 1)
  };
  // u in [0, 1); never an index of weight 0.
  Choice sample(float u) const {
    std::size_t lo = 0, hi = pmf_.size();  // cdf_[lo] <= u < cdf_[hi]
    while (hi - lo > 1) {
      const std::size_t mid = (lo + hi) / 2;
      (double(u) < cdf_[mid] ? hi : lo) = mid;
    }
    const double rest = (double(u) - cdf_[lo]) / (cdf_[lo + 1] - cdf_[lo]);
    return {std::uint32_t(lo), rest < 0x1.fffffep-1 ? float(rest) : 0x1.fffffep-1f};
  }

 private:
  std::vector<double> cdf_;  // size + 1 entries, 0 to exactly 1
  std::vector<float> pmf_;
};

}  // namespace loom::pathtrace
