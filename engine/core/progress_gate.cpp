#include "progress_gate.hpp"

namespace loom::detail {

bool ProgressGate::admit(double fraction, std::string_view label) {
  if (label != label_) {  // a new phase starts its own count
    label_ = label;
    last_ = fraction;
    return true;
  }
  // Same phase: forward only, in steps of 1% (and the final 100% once).
  if (fraction <= last_) return false;
  if (fraction < last_ + 0.01 && fraction < 1.0) return false;
  last_ = fraction;
  return true;
}

}  // namespace loom::detail
