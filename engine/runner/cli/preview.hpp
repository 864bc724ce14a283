// `loom run --preview FILE [--preview-every S]`: the partial images nodes
// publish while they run (Context::publish_partial, e.g. PathTrace after each
// pass) written to FILE at most every S seconds, so a long render can be
// watched from an image viewer that reloads the file. The file is written by
// SaveImage's own body (the runner loads it up front), so it is encoded by the image's
// tag as SaveImage would, and atomically: a viewer never reads half a file.
// Partials are only shown: sinks still write the final results.
#pragma once

#include <chrono>
#include <filesystem>
#include <mutex>
#include <string>

#include "cli/run_settings.hpp"
#include "loom/evaluator.hpp"
#include "loom/registry.hpp"

namespace loom::runner {

class PreviewWriter final : public Observer {
 public:
  // Passes every report on to `next` (the console). `save` is SaveImage.
  PreviewWriter(Observer& next, const NodeType& save, std::filesystem::path file, double every_seconds);

  void node_started(const std::string& id, const std::string& type) override { next_.node_started(id, type); }
  void node_progress(const std::string& id, double fraction, const std::string& label) override {
    next_.node_progress(id, fraction, label);
  }
  void node_message(const std::string& id, bool warning, const std::string& text) override {
    next_.node_message(id, warning, text);
  }
  void node_finished(const std::string& id, const NodeReport& report) override { next_.node_finished(id, report); }
  void frame_started(int frame, int index, int count) override { next_.frame_started(frame, index, count); }
  // Yes only when a write is due: a node builds no partial value otherwise.
  bool wants_partial(const std::string& id) const override;
  void node_partial(const std::string& id, const std::string& output, const Value& value,
                    const PartialInfo& info) override;

  int written() const { return written_; }

 private:
  using Clock = std::chrono::steady_clock;
  Observer& next_;
  const NodeType& save_;
  const std::filesystem::path file_;
  const Clock::duration every_;
  mutable std::mutex mutex_;
  Clock::time_point last_{};
  int written_ = 0;
  bool failed_ = false;  // a write failed (said once): no more previews
};

// SaveImage, its plugin loaded; null (the reason printed) when it cannot be.
const NodeType* save_image_type(LoadedGraph& loaded);

}  // namespace loom::runner
