// Internal: what a node body reaches through Inputs and Context during one
// evaluation (lazy inputs, progress, messages, cancellation, scratch store).
#pragma once

#include <deque>
#include <mutex>
#include <string>

#include "evaluation.hpp"
#include "progress_gate.hpp"

namespace loom::detail {

class Host final : public NodeHost {
 public:
  Host(Evaluation& e, NodeState& s) : e_(e), s_(s) {}

  Value fetch_input(int i) override;
  bool input_set(int i) const override;
  void report_progress(double fraction, std::string_view label) override;
  void report(bool warning, std::string text) override;
  bool cancelled() const override { return e_.cancelled(); }
  std::shared_ptr<void> scratch(std::uint64_t key,
                                const std::function<std::shared_ptr<void>()>& make) override;
  std::shared_ptr<void> sequence_state(const std::function<std::shared_ptr<void>()>& make) override;
  void depends_on_file(const std::filesystem::path& path) override;
  PixelRegion pixel_region() const override;
  void sum_over_parts(double* values, std::size_t count, double work) override;
  int take_slot() override;
  bool partial_wanted() const override;
  void publish_partial(std::string_view output, Value value, const PartialInfo& info) override;

 private:
  Evaluation& e_;
  NodeState& s_;
  std::mutex mutex_;
  std::deque<Value> resolved_paths_;  // linked paths resolved here: in.get returns references into them
  ProgressGate progress_;
};

}  // namespace loom::detail
