// Internal: the state of one evaluation, shared by the files the evaluator is
// split into (plan.cpp binds, orders and hashes; computation_hash.cpp holds the
// hash rule; node_host.cpp serves node bodies; evaluator.cpp schedules and runs).
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string_view>
#include <thread>
#include <unordered_map>
#include <vector>

#include "input_binding.hpp"
#include "loom/evaluator.hpp"

namespace loom {

namespace detail {

// A file a result depends on, as it was when the result was computed: its
// size and modification time (the rule make and the literal input files'
// hash use). A result whose files changed is not reused.
struct FileStamp {
  std::string path;
  std::int64_t size = -1;
  std::int64_t mtime = -1;
  bool operator==(const FileStamp& o) const { return path == o.path && size == o.size && mtime == o.mtime; }
};
FileStamp stamp_of(const std::string& path);
bool still_current(const std::vector<FileStamp>& files);
json stamps_to_json(const std::vector<FileStamp>& files);
std::optional<std::vector<FileStamp>> stamps_from_json(const json& j);

}  // namespace detail

struct Session::State {
  explicit State(const Registry& r) : registry(r) {}
  const Registry& registry;

  // The memory cache. An ordinary entry lives while it was used in one of
  // the last two frames evaluated; a simulation state (`state`) lives under
  // the state memory budget, least recently used first out.
  struct CacheEntry {
    std::vector<Value> outputs;
    std::vector<detail::FileStamp> files;  // what the result read, its upstream's included
    double seconds = 0;  // what computing it took
    std::uint64_t generation = 0;
    bool state = false;
    std::size_t bytes = 0;  // states only
  };
  std::mutex cache_mutex;
  std::unordered_map<std::uint64_t, CacheEntry> cache;
  std::uint64_t generation = 0;
  std::uint64_t evaluations = 0;
  // Per simulation chain (its hash at the start frame): the latest state
  // computed, kept outside the budget (while the chain is in use) so stepping
  // on never restarts, and the step time spent since a state of the chain was
  // last written to disk.
  struct LatestState {
    int frame = 0;
    std::vector<Value> outputs;
    std::vector<detail::FileStamp> files;
    double seconds = 0;
    std::uint64_t generation = 0;  // last used
  };
  std::unordered_map<std::uint64_t, LatestState> latest_states;
  std::unordered_map<std::uint64_t, double> unsaved_seconds;

  // Sequence sinks' state (Context::sequence_state), for one evaluate() call.
  std::mutex sequence_mutex;
  std::map<std::string, std::shared_ptr<void>> sequences;

  static constexpr std::size_t kScratchPerNode = 4;
  std::mutex scratch_mutex;
  std::map<std::string, std::deque<std::pair<std::uint64_t, std::shared_ptr<void>>>> scratch;
};

namespace detail {

// Thrown into a node body when a lazily fetched input's upstream failed.
struct UpstreamFailed : Error {
  using Error::Error;
};

// A node's place in Evaluation::nodes.
using NodeIndex = std::size_t;

struct NodeState {
  const GraphNode* node = nullptr;
  const NodeType* type = nullptr;
  struct Binding {
    enum Kind { unset, literal, link } kind = unset;
    Value literal_value;
    std::uint64_t iteration_hash = 0;  // a value Repeat gives: hashed by this, not its JSON
    NodeIndex upstream = 0;  // a link's node
    int output = -1;
  };
  std::vector<Binding> inputs;  // one per declared input
  std::uint64_t hash = 0;
  std::uint64_t seed = 0;
  bool cacheable = false;
  bool time_dependent = false;  // its own flag, a simulation, or a time-dependent upstream
  // Simulations: the state input's index, the chain (the node's hash at the
  // start frame) and, past the start frame, its outputs at the previous frame.
  int state_input = -1;
  int state_output = -1;
  std::uint64_t chain = 0;
  std::vector<Value> previous;

  std::atomic<bool> claimed{false};  // one thread runs the node...
  std::atomic<bool> done{false};     // ...and sets this when it has finished
  bool ok = false;  // ran or cached
  NodeReport report;
  std::vector<Value> outputs;
  // The files the result depends on beyond its hash: linked input files,
  // files the body declared (Context::depends_on_file), and its linked
  // upstream results' files. Kept with the result; see FileStamp.
  std::mutex files_mutex;
  std::vector<FileStamp> files;
  void add_files(const std::vector<FileStamp>& more);
};

// "input "NAME": node "ID" failed": why a node cannot use an input whose
// upstream node did not run or failed.
std::string upstream_failure(const InputSpec& input, const NodeState& upstream);

// Where a result is kept (see Evaluation::kept).
enum class Kept { nowhere, memory, disk };

struct Evaluation {
  Session::State& session;
  const Graph& graph;
  const EvalOptions& options;
  std::vector<std::unique_ptr<NodeState>> nodes;
  std::unordered_map<std::string_view, NodeIndex> index;  // views of graph.nodes' keys
  const std::filesystem::path graph_dir;
  const FrameTime time;  // step is set per node
  const BindingPlace place;  // what paths bound to inputs resolve against
  // A simulation stepping through frames evaluates the graph at each frame
  // with its previous outputs handed in here (see step_to_previous in simulation.cpp).
  std::optional<NodeIndex> stepping_node;
  std::vector<Value> stepping_previous;
  // A Repeat body's iteration: values given to inner inputs (node id, input) with
  // the hash each stands for (repeat.cpp).
  const std::map<std::pair<std::string, std::string>, std::pair<Value, std::uint64_t>>* iteration_values = nullptr;
  // What the ids of this evaluation's nodes are prefixed with in the
  // session's per-node state (scratch, sequence state): a Repeat body's node
  // "save" is "loop.save" there, so that with cache_iterations (the outer
  // session) it never shares the state of a top-level "save".
  std::string scope;
  std::string scoped_id(const NodeState& s) const { return scope + s.node->id; }

  Evaluation(Session::State& s, const Graph& g, const EvalOptions& o, FrameTime t)
      : session(s), graph(g), options(o), graph_dir(g.dir()), time(t),
        place{graph_dir, o.output_dir, o.allow_outside_output, t.frame} {}

  NodeState& at(NodeIndex n) { return *nodes[n]; }
  bool cancelled() const { return options.cancel && options.cancel->load(std::memory_order_relaxed); }
  // Past the start frame a simulation's state input is its own previous
  // output, not the initial state linked in the graph.
  bool takes_previous_state(const NodeState& s, std::size_t input) const {
    return s.state_input == static_cast<int>(input) && time.frame > time.start;
  }
  bool links_upstream(const NodeState& s, std::size_t input) const {
    return s.inputs[input].kind == NodeState::Binding::link && !takes_previous_state(s, input);
  }

  // result_cache.cpp. The one answer to "is the result of s at `hash` kept?":
  // the memory cache, then the simulation chain's latest state, then the disk
  // cache (asked, not read).
  Kept kept(const NodeState& s, std::uint64_t hash);
  struct MemoryHit {
    const std::vector<Value>* outputs = nullptr;  // null: not in memory
    const std::vector<FileStamp>* files = nullptr;
    double seconds = 0;
  };
  MemoryHit memory_entry(const NodeState& s, std::uint64_t hash, bool touch);
  // The kept result, read from where kept() finds it, with the files it
  // depends on (a disk entry that fails to read or does not fit the node's
  // outputs is a miss, and so is a result whose files changed).
  struct Found {
    std::vector<Value> outputs;
    std::vector<FileStamp> files;
    double seconds = 0;  // what computing it took, kept with it
    bool from_disk = false;
  };
  std::optional<Found> cache_find(const NodeState& s, std::uint64_t hash);
  void cache_put(NodeState& s, double seconds);

  // A linked value given to a group's interface input is also checked by the
  // interface's declaration (range, choices) where it reaches an inner input:
  // per (node, input), the instance paths and declarations (plan.cpp).
  std::map<std::pair<const NodeState*, int>, std::vector<std::pair<std::string, InputSpec>>> interface_checks;
  void collect_interface_checks();
  void check_interface_inputs(const NodeState& s, int input, const Value& value) const;

  // plan.cpp: node states, input bindings, topological order, hashes.
  void build();
  void bind_inputs();
  bool bind_iteration_value(const NodeState& s, const InputSpec& spec, NodeState::Binding& b);
  std::vector<NodeIndex> topological_order() const;
  void hash_nodes(const std::vector<NodeIndex>& order);
  void share_equal_results(const std::vector<NodeIndex>& order);

  // evaluator.cpp: runs the closure of `roots` on the TBB arena.
  void execute(const std::vector<NodeIndex>& roots);
  // Runs node n unless another thread does or did. Contention only happens when
  // a lazy fetch and the scheduler reach the same node; the loser waits. The
  // winner never waits on the loser (node bodies run isolated, and the graph is
  // acyclic), so waiting cannot deadlock.
  void run_once(NodeIndex n) {
    NodeState& s = at(n);
    if (s.done.load(std::memory_order_acquire)) return;
    if (!s.claimed.exchange(true, std::memory_order_acq_rel)) return run_node(n);
    while (!s.done.load(std::memory_order_acquire)) std::this_thread::yield();
  }
  // node_runner.cpp: one node, in four steps (see there).
  void run_node(NodeIndex n);
  bool settled_without_running(NodeIndex n);
  bool take_cached(NodeState& s);
  bool ensure_inputs(NodeState& s);
  struct Outcome {
    NodeStatus status = NodeStatus::failed;
    std::string error;
    std::vector<Value> outputs;
    double seconds = 0;
  };
  Outcome invoke(NodeState& s);
  void gather_parts(NodeState& s, Outputs& out, const std::function<void()>& run_again);
  void record(NodeState& s, Outcome outcome);
  // Simulations past the start frame: fills s.previous with the outputs at
  // frame - 1, stepping from the latest cached frame. False if it could not.
  bool step_to_previous(NodeIndex n);
  void finish(NodeState& s) {
    s.done.store(true, std::memory_order_release);
    if (options.observer) options.observer->node_finished(s.node->id, s.report);
  }
};

// repeat.cpp: a Repeat node's body, run `count` times.
void run_repeat(Evaluation& outer, NodeState& s, Inputs& in, Outputs& out, Context& ctx);

// End of a frame: drops ordinary entries unused for two frames, simulation
// states beyond the budget (least recently used first) and unused chains.
void evict(Session::State& st, std::size_t state_budget);

}  // namespace detail
}  // namespace loom
