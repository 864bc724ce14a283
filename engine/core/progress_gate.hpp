// Internal: what a node's progress reports become on the way to the observer.
// Context::progress may be called from any thread (also from inside
// tbb::parallel_for bodies): the gate serializes the calls, drops reports that
// would run a label's fraction backwards, and throttles to 1% steps.
#pragma once

#include <mutex>
#include <string>
#include <string_view>

namespace loom::detail {

class ProgressGate {
 public:
  // Calls show(fraction, label) for a report worth showing, under the gate's
  // lock, so that what the observer sees is in order and monotone per label.
  template <class Show>
  void offer(double fraction, std::string_view label, Show&& show) {
    std::lock_guard lock(mutex_);
    if (!admit(fraction, label)) return;
    show(last_, label_);
  }

 private:
  bool admit(double fraction, std::string_view label);
  std::mutex mutex_;
  double last_ = -1;
  std::string label_;
};

}  // namespace loom::detail
