// Evaluation: what the runner and the editor call.
//
// A Session owns the cache. evaluate() plans from the requested targets (sinks
// by default), prunes what they do not need, runs independent nodes in
// parallel on a TBB arena of `threads` workers, fetches lazy inputs only when a
// node asks, and reuses every result whose computation hash it has seen:
// hash = node type + version + for each input either its literal value or the
// hash of the upstream node feeding it (Gaffer's contract). Re-evaluating after
// one change therefore recomputes only what depends on that change.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "loom/graph.hpp"

namespace loom {

enum class NodeStatus { pruned, ran, cached, skipped, failed };
LOOM_API const char* to_string(NodeStatus status);

struct NodeReport {
  NodeStatus status = NodeStatus::pruned;
  double seconds = 0;         // run time of the node body (0 unless ran/failed)
  std::string error;          // failed or skipped: why
  std::vector<std::string> warnings;
};

struct Target {
  std::string node;
  std::string output;  // empty: every output of the node
};
// Parses "ID" or "ID.OUTPUT".
LOOM_API Target parse_target(const std::string& text);

// Called from worker threads: implementations must be thread-safe.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void node_started(const std::string& /*id*/, const std::string& /*type*/) {}
  virtual void node_progress(const std::string& /*id*/, double /*fraction*/,
                             const std::string& /*label*/) {}
  virtual void node_message(const std::string& /*id*/, bool /*warning*/,
                            const std::string& /*text*/) {}
  virtual void node_finished(const std::string& /*id*/, const NodeReport& /*report*/) {}
};

struct EvalOptions {
  std::vector<Target> targets;  // empty: every sink in the graph
  int threads = 0;              // 0: all cores
  std::filesystem::path output_dir = ".";
  // Output paths (literal or linked) must resolve under output_dir unless
  // this is set: absolute paths and ".." that climb out are refused.
  bool allow_outside_output = false;
  Observer* observer = nullptr;
  const std::atomic<bool>* cancel = nullptr;  // set it to cancel cooperatively
};

struct EvalResult {
  std::map<std::string, NodeReport> nodes;  // every node of the graph
  std::map<std::string, std::vector<Value>> outputs;  // the targets' outputs
  double total_seconds = 0;
  bool cancelled = false;
  bool ok() const;  // no node failed or was skipped
};

class LOOM_API Session {
 public:
  explicit Session(const Registry& registry);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // The graph must have passed validate_graph with the same registry.
  EvalResult evaluate(const Graph& graph, const EvalOptions& options = {});

  std::size_t cache_entries() const;
  void clear_cache();

  struct State;  // opaque: the cache and per-node scratch

 private:
  std::unique_ptr<State> state_;
};

}  // namespace loom
