// Host API. Evaluation: what the runner and the editor call.
//
// A Session owns the cache. evaluate() plans from the requested targets (sinks
// by default), prunes what they do not need, runs independent nodes in
// parallel on a TBB arena of `threads` workers, fetches lazy inputs only when a
// node asks, and reuses every result whose computation hash it has seen:
// hash = node type + version + for each input either its literal value or the
// hash of the upstream node feeding it (Gaffer's contract). Re-evaluating after
// one change therefore recomputes only what depends on that change.
//
// Time: evaluate() walks options.frames in order. A node's hash has the frame
// in it only if it reads time (its own flag, a simulation, or an upstream
// hash with the frame in it), so time-independent results are computed once
// and shared by every frame. A simulation's state at frame f is keyed by
// H(its hash at the start frame, f) and stepped from the latest cached frame.
// See docs/architecture.md, "Time, state and the persistent cache".
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "loom/graph.hpp"

namespace loom {

enum class NodeStatus { pruned, ran, cached, skipped, failed };
LOOM_API const char* to_string(NodeStatus status);

struct NodeReport {
  // Over several frames: failed, else skipped, else ran (at some frame), else
  // cached, else pruned.
  NodeStatus status = NodeStatus::pruned;
  double seconds = 0;         // run time of the node body (0 unless ran/failed), summed over frames
  // What computing its results took, wherever they came from: the body's
  // run time where it ran, the run time kept with a result read from a cache
  // (a rerun's or a resumed task's), summed over frames.
  double compute_seconds = 0;
  int runs = 0;               // frames (or simulation steps) at which the body ran
  int memory_hits = 0;        // frames served by the memory cache
  int disk_hits = 0;          // frames served by the persistent cache
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
  // Before each frame of a frame range: frame number, index (1-based) and count.
  virtual void frame_started(int /*frame*/, int /*index*/, int /*count*/) {}
  // Partial results (Context::publish_partial). Asked before each publish:
  // a node builds its partial value only when this says yes for its id, so
  // answer cheaply. node_partial runs on the node's thread, which waits for
  // it: copy what you keep (the value is shared and immutable) and return.
  virtual bool wants_partial(const std::string& /*id*/) const { return false; }
  virtual void node_partial(const std::string& /*id*/, const std::string& /*output*/,
                            const Value& /*value*/, const PartialInfo& /*info*/) {}
};

struct FrameRange {
  int first = 1, last = 1;  // inclusive, first <= last
};

class DiskCache;

// One image computed in parts by several processes (MPI ranks, engine/runner):
// a node declared set_pixel_independent() computes region(node) in every
// process, and combine() replaces its outputs with the whole images, gathered
// from every part (split by samples, the node already holds the whole: it
// summed its samples with sum() after each pass). Called from a worker thread of the evaluation; combine()
// waits for the other processes. See docs/architecture.md.
class PixelSplit {
 public:
  virtual ~PixelSplit() = default;
  // The part of `node`'s images this process computes (whole: not split).
  virtual PixelRegion region(const std::string& node) const = 0;
  // `outputs` hold this process's part on entry and the whole on return.
  virtual void combine(const std::string& node, const NodeSpec& spec, std::vector<Value>& outputs) const = 0;
  // Split by samples: `values` summed over the processes, on every process;
  // `work` is this process's since its last sum (Context::sum_over_parts).
  virtual void sum(double* values, std::size_t count, double work) const = 0;
  // Split by samples and dealt as processes ask: the next slot of the pass
  // for this process, or -1 when the pass's slots are all taken
  // (Context::take_slot).
  virtual int take_slot() const { return -1; }
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
  // The frames to evaluate, in order; unset: the graph's start frame only (1
  // for a graph without "time"). Sinks run at every frame; nodes that do not
  // depend on time run once and are shared by every frame.
  std::optional<FrameRange> frames;
  // The persistent result cache, or null for none (see loom/disk_cache.hpp).
  DiskCache* disk_cache = nullptr;
  // Memory kept for simulation states (besides each simulation's latest
  // state); older states beyond it are dropped (the disk cache may hold them).
  std::size_t state_memory_budget = std::size_t(2) << 30;
  // Set when this process computes only a part of pixel-independent nodes'
  // images (an MPI run); null: every node computes every pixel.
  const PixelSplit* pixel_split = nullptr;
};

struct EvalResult {
  std::map<std::string, NodeReport> nodes;  // every node of the graph
  std::map<std::string, std::vector<Value>> outputs;  // the targets' outputs at the last frame evaluated
  // Over several frames: each target's outputs at every frame evaluated, in
  // frame order (what `--target` prints as a list, one entry per frame).
  std::map<std::string, std::vector<std::vector<Value>>> outputs_per_frame;
  double total_seconds = 0;
  int frames = 0;  // frames evaluated (fewer than asked when cancelled or failed)
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

  // The frames of `frames` at which the outputs of `node` are kept in this
  // session's memory cache or in options.disk_cache (hashed as evaluate()
  // would, with options' output folder): what a time slider marks. A sink or
  // nondeterministic node has none. Call it from the thread that calls
  // evaluate(), never during one. Throws Error for an unknown node.
  std::vector<int> cached_frames(const Graph& graph, const std::string& node, FrameRange frames,
                                 const EvalOptions& options = {});

  std::size_t cache_entries() const;
  void clear_cache();

  struct State;  // opaque: the cache and per-node scratch

 private:
  std::unique_ptr<State> state_;
};

}  // namespace loom
