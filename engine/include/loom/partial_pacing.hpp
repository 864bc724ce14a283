// Plugin author API. When a node publishes its next partial result
// (Context::publish_partial) inside long work: at most every kSeconds, so a
// viewer gets 10-12 images a second however long each step of the work is
// (an image or mesh made per step would cost more than the step when steps
// are short, and show too little when they are long).
#pragma once

#include <chrono>

namespace loom {

class PartialPacing {
 public:
  static constexpr double kSeconds = 0.08;

  // Whether kSeconds have passed since the last published() (or since this
  // was made).
  bool due() const { return std::chrono::duration<double>(Clock::now() - last_).count() >= kSeconds; }
  void published() { last_ = Clock::now(); }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point last_ = Clock::now();
};

}  // namespace loom
