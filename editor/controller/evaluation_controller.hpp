// Background evaluation for the editor: one worker thread owns the Session
// (and so the cache); the UI thread submits the graph after every edit and
// picks up finished results without ever waiting on a node.
//
// A new request cancels the running evaluation through EvalOptions::cancel;
// the worker then starts on the newest request only (requests in between are
// dropped). Because the Session keeps its cache across requests, only what an
// edit touched recomputes. Values are immutable and shared, so a finished
// result is handed to the UI thread by pointer.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "loom/evaluator.hpp"
#include "model/node_issue.hpp"

namespace loom::editor {

struct EvalRequest {
  json document;                     // the graph file's JSON
  std::filesystem::path file;        // for relative input paths and messages
  std::vector<Target> targets;       // empty: every sink
  std::filesystem::path output_dir;  // where sinks write
  std::uint64_t revision = 0;        // the model's revision this came from
  std::optional<FrameRange> frames;  // unset: the graph's start frame
  // Whose cached frames (over the graph's time range) to report afterwards:
  // the time slider's marks. Empty: none.
  std::string frames_of;
};

// A finished (or cancelled, or invalid) evaluation.
struct Evaluation {
  std::uint64_t revision = 0;
  std::vector<Target> targets;
  EvalResult result;
  std::vector<NodeIssue> issues;   // validation: the graph did not run
  std::string error;               // anything else that stopped the run
  double seconds = 0;              // wall time from start to finish
  int frame = 0;                   // the (last) frame evaluated; 0: no frames asked for
  std::string frames_of;           // the request's
  std::vector<int> cached_frames;  // frames of `frames_of` the session keeps, after this run
};

// What a node is doing right now, for the canvas while a run is under way.
struct LiveNode {
  bool running = false;
  double progress = 0;  // 0..1
  std::string label;
};

class EvaluationController {
 public:
  // The registry must hold every node type the graphs use and outlive this.
  explicit EvaluationController(const Registry& registry, int threads = 0);
  ~EvaluationController();  // cancels the running evaluation and joins
  EvaluationController(const EvaluationController&) = delete;
  EvaluationController& operator=(const EvaluationController&) = delete;

  // Replaces any pending request and cancels the running one. With
  // `cancel_running` false (a drag in progress) the running evaluation
  // finishes and is shown first: cancelling on every mouse move would leave a
  // drag whose solve takes longer than a frame with no result at all.
  void submit(EvalRequest request, bool cancel_running = true);
  // Drops the pending request and cancels the running one (the editor does
  // this before a plugin reload, then waits until !busy()).
  void cancel();
  // The newest evaluation that finished since the last call, if any.
  std::optional<std::shared_ptr<const Evaluation>> take_finished();
  std::shared_ptr<const Evaluation> latest() const;  // the newest finished one
  std::map<std::string, LiveNode> live() const;
  bool busy() const;  // a request is pending or running
  // Blocks until idle (tests and the command line, never the UI loop).
  void wait_idle();

 private:
  class Progress;
  void work();
  std::shared_ptr<Evaluation> run(const EvalRequest& request);

  const Registry& registry_;
  int threads_;
  Session session_;
  std::unique_ptr<Progress> progress_;

  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::optional<EvalRequest> pending_;
  bool running_ = false, stop_ = false, fresh_ = false;
  std::shared_ptr<const Evaluation> latest_;
  std::atomic<bool> cancel_{false};
  std::thread worker_;
};

}  // namespace loom::editor
