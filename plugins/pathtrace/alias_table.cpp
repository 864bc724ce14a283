#include "alias_table.hpp"

#include <algorithm>
#include <cmath>

namespace loom::pathtrace {

AliasTable::AliasTable(const std::vector<double>& weights) {
  for (double w : weights) total_ += (w > 0 && std::isfinite(w)) ? w : 0;
  if (!(total_ > 0)) return;
  const std::size_t n = weights.size();
  bins_.resize(n);
  // Scaled probabilities n * p_i: bins below 1 borrow the rest from one above 1.
  std::vector<double> scaled(n);
  std::vector<std::uint32_t> small, large;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = (weights[i] > 0 && std::isfinite(weights[i])) ? weights[i] : 0;
    bins_[i].p = float(w / total_);
    scaled[i] = w / total_ * double(n);
    (scaled[i] < 1 ? small : large).push_back(std::uint32_t(i));
  }
  while (!small.empty() && !large.empty()) {
    const std::uint32_t s = small.back(), l = large.back();
    small.pop_back();
    bins_[s].q = float(scaled[s]);
    bins_[s].alias = l;
    scaled[l] -= 1 - scaled[s];
    if (scaled[l] < 1) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // Left-overs are 1 up to rounding.
  for (std::uint32_t i : small) bins_[i] = {1, bins_[i].p, i};
  for (std::uint32_t i : large) bins_[i] = {1, bins_[i].p, i};
}

}  // namespace loom::pathtrace
