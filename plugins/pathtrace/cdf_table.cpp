#include "cdf_table.hpp"

#include <cmath>

namespace loom::pathtrace {

CdfTable::CdfTable(const std::vector<double>& weights) {
  double total = 0;
  for (double w : weights) total += (w > 0 && std::isfinite(w)) ? w : 0;
  if (!(total > 0)) return;
  cdf_.assign(weights.size() + 1, 0.0);
  pmf_.resize(weights.size());
  double sum = 0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    const double w = (weights[i] > 0 && std::isfinite(weights[i])) ? weights[i] : 0;
    pmf_[i] = float(w / total);
    sum += w;
    cdf_[i + 1] = sum / total;
  }
  // Exactly 1 at the end, and zero-weight entries at the end as well (their
  // interval is empty: u < 1 never lands in them).
  const double last = cdf_.back();
  for (std::size_t i = weights.size(); i > 0 && cdf_[i] >= last; --i) cdf_[i] = 1;
}

}  // namespace loom::pathtrace
