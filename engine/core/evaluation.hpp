// Internal: the state of one evaluation, shared by the files the evaluator is
// split into (plan.cpp binds, orders and hashes; computation_hash.cpp holds the
// hash rule; node_host.cpp serves node bodies; evaluator.cpp schedules and runs).
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string_view>
#include <thread>
#include <unordered_map>
#include <vector>

#include "loom/evaluator.hpp"

namespace loom {

struct Session::State {
  explicit State(const Registry& r) : registry(r) {}
  const Registry& registry;

  struct CacheEntry {
    std::vector<Value> outputs;
    std::uint64_t generation = 0;
  };
  std::mutex cache_mutex;
  std::unordered_map<std::uint64_t, CacheEntry> cache;
  std::uint64_t generation = 0;
  std::uint64_t evaluations = 0;

  static constexpr std::size_t kScratchPerNode = 4;
  std::mutex scratch_mutex;
  std::map<std::string, std::deque<std::pair<std::uint64_t, std::shared_ptr<void>>>> scratch;
};

namespace detail {

// Thrown into a node body when a lazily fetched input's upstream failed.
struct UpstreamFailed : Error {
  using Error::Error;
};

struct NodeState {
  const GraphNode* node = nullptr;
  const NodeType* type = nullptr;
  struct Binding {
    enum Kind { unset, literal, link } kind = unset;
    Value literal_value;
    int upstream = -1;
    int output = -1;
  };
  std::vector<Binding> inputs;  // one per declared input
  std::uint64_t hash = 0;
  std::uint64_t seed = 0;
  bool cacheable = false;

  std::atomic<bool> claimed{false};  // one thread runs the node...
  std::atomic<bool> done{false};     // ...and sets this when it has finished
  bool ok = false;  // ran or cached
  NodeReport report;
  std::vector<Value> outputs;
};

struct Evaluation {
  Session::State& session;
  const Graph& graph;
  const EvalOptions& options;
  std::vector<std::unique_ptr<NodeState>> nodes;
  std::unordered_map<std::string_view, int> index;  // views of graph.nodes' keys
  const std::filesystem::path graph_dir;

  Evaluation(Session::State& s, const Graph& g, const EvalOptions& o)
      : session(s), graph(g), options(o), graph_dir(g.dir()) {}

  NodeState& at(int n) { return *nodes[static_cast<std::size_t>(n)]; }
  bool cancelled() const { return options.cancel && options.cancel->load(std::memory_order_relaxed); }

  bool cache_has(std::uint64_t hash) {
    std::lock_guard lock(session.cache_mutex);
    return session.cache.count(hash) != 0;
  }

  // plan.cpp: node states, input bindings, topological order, hashes.
  void build();
  void bind_inputs();
  std::vector<int> topological_order() const;
  void hash_nodes(const std::vector<int>& order);

  // evaluator.cpp: runs the closure of `roots` on the TBB arena.
  void execute(const std::vector<int>& roots);
  // Runs node n unless another thread does or did. Contention only happens when
  // a lazy fetch and the scheduler reach the same node; the loser waits. The
  // winner never waits on the loser (node bodies run isolated, and the graph is
  // acyclic), so waiting cannot deadlock.
  void run_once(int n) {
    NodeState& s = at(n);
    if (s.done.load(std::memory_order_acquire)) return;
    if (!s.claimed.exchange(true, std::memory_order_acq_rel)) return run_node(n);
    while (!s.done.load(std::memory_order_acquire)) std::this_thread::yield();
  }
  void run_node(int n);
  void finish(NodeState& s) {
    s.done.store(true, std::memory_order_release);
    if (options.observer) options.observer->node_finished(s.node->id, s.report);
  }
};

}  // namespace detail
}  // namespace loom
