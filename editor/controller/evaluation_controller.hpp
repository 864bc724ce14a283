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
#include "loom/graph_view.hpp"
#include "model/node_issue.hpp"

namespace loom::editor {

struct EvalRequest {
  json document;                     // the graph file's JSON
  std::filesystem::path file;        // for relative input paths and messages
  std::vector<Target> targets;       // empty: every sink (unless `preview`)
  // Set: the preview instead of `targets`: every output of every node that
  // is not a sink, of the top graph and of the group level whose nodes are
  // named with this prefix ("look." inside instance look; "" for none).
  std::optional<std::string> preview;
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
  std::optional<std::string> preview;  // the request's (unset: its targets or the sinks)
  std::vector<Target> targets;
  EvalResult result;
  // The graph evaluated and the engine's view of it (null when it did not
  // load): what each result is called, which nodes a group instance holds.
  std::shared_ptr<const Graph> graph;
  std::shared_ptr<const GraphView> view;
  // Each group instance's status, summed over its inner nodes (by path).
  std::map<std::string, NodeReport> instance_reports;
  std::vector<NodeIssue> issues;   // validation: the graph did not run
  std::string error;               // anything else that stopped the run
  double seconds = 0;              // wall time from start to finish
  int frame = 0;                   // the (last) frame evaluated; 0: no frames asked for
  std::string frames_of;           // the request's
  std::vector<int> cached_frames;  // frames of `frames_of` the session keeps, after this run

  // A node's report by its path in the evaluated graph: a flat node's, or a
  // group instance's summary; null when the run did not reach it.
  const NodeReport* report(const std::string& node) const;
  // The value of NODE.OUTPUT (a flat node or a group instance, by path) at
  // the last frame evaluated, found under the name the engine's view gives
  // it; empty when it was not a target or did not compute.
  Value output(const std::string& node, const std::string& output) const;
};

// The newest partial value a running node published (Context::publish_partial,
// e.g. PathTrace after each pass): shown until its evaluation finishes.
struct Partial {
  std::uint64_t revision = 0;  // of the request whose run published it
  Value value;
  double done = 0, total = 0;  // e.g. samples per pixel so far, and asked for
  std::string unit;            // what `done` counts ("spp")
  double relative_error = -1;  // estimated relative error of the mean; < 0: unknown
  double seconds = 0;          // since the node started
  std::uint64_t serial = 0;    // rises with every partial of the controller
};

// What a node is doing right now, for the canvas while a run is under way:
// running, or finished in this run (its report), so that the nodes a long
// one waits behind show what they did before the run ends.
struct LiveNode {
  bool running = false;
  double progress = 0;  // 0..1
  std::string label;
  NodeReport report;  // once finished (running false)
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
  // drag whose solve takes longer than a frame with no result at all. (A
  // run that is refining() has shown a pass already: the editor cancels it.)
  void submit(EvalRequest request, bool cancel_running = true);
  // Drops the pending request and cancels the running one (the editor does
  // this before a plugin reload, then waits until !busy()).
  void cancel();
  // The newest evaluation that finished since the last call, if any.
  std::optional<std::shared_ptr<const Evaluation>> take_finished();
  std::shared_ptr<const Evaluation> latest() const;  // the newest finished one
  std::map<std::string, LiveNode> live() const;
  // The newest partial value of NODE.OUTPUT (by the engine's name, a flat
  // node's id) published by the running or the last evaluation; empty when
  // none since that evaluation started.
  std::optional<Partial> partial(const std::string& node, const std::string& output) const;
  // Whether the running evaluation has published a partial value: it shows
  // something within a pass, so a drag may cancel it (see submit).
  bool refining() const;
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
