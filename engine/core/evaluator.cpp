// Scheduling: the closure of the requested nodes runs on a TBB task group as
// inputs become ready; Session::evaluate walks the frames. The plan (bindings,
// order, hashes) is in plan.cpp, the hash rule in computation_hash.cpp, one
// node's run in node_runner.cpp, what node bodies reach in node_host.cpp, the
// caches' policy in result_cache.cpp, simulation stepping in simulation.cpp.
#include "loom/evaluator.hpp"

#include <algorithm>
#include <tbb/info.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "evaluation.hpp"
#include "graph_groups.hpp"
#include "graph_time.hpp"
#include "loom/graph_view.hpp"

namespace loom {

const char* to_string(NodeStatus s) {
  switch (s) {
    case NodeStatus::pruned: return "pruned";
    case NodeStatus::ran: return "ran";
    case NodeStatus::cached: return "cached";
    case NodeStatus::skipped: return "skipped";
    case NodeStatus::failed: return "failed";
  }
  return "?";
}

Target parse_target(const std::string& text) {
  if (auto link = parse_link(text)) return {link->node, link->output};
  return {text, ""};  // a node id alone: every output
}

bool EvalResult::ok() const {
  for (const auto& [id, r] : nodes)
    if (r.status == NodeStatus::failed || r.status == NodeStatus::skipped) return false;
  return !cancelled;
}

namespace detail {

void Evaluation::execute(const std::vector<NodeIndex>& roots) {
  // The closure of the roots over non-lazy links, stopping at finished nodes
  // and at cache hits (a hit needs none of its inputs).
  const std::size_t n_all = nodes.size();
  std::vector<char> member(n_all, 0), hit(n_all, 0);
  std::vector<NodeIndex> members, stack;
  auto visit = [&](NodeIndex n) {
    if (member[n] || nodes[n]->done.load(std::memory_order_acquire)) return;
    member[n] = 1;
    stack.push_back(n);
  };
  for (NodeIndex r : roots) visit(r);
  while (!stack.empty()) {
    const NodeIndex n = stack.back();
    stack.pop_back();
    members.push_back(n);
    NodeState& s = at(n);
    if (s.cacheable && kept(s, s.hash) != Kept::nowhere) {
      hit[n] = 1;
      continue;
    }
    const auto& specs = s.type->spec.inputs;
    for (std::size_t i = 0; i < s.inputs.size(); ++i)
      if (links_upstream(s, i) && !specs[i].lazy) visit(s.inputs[i].upstream);
  }
  // For each member, how many distinct member inputs it waits on, and who
  // waits on whom.
  std::vector<std::atomic<int>> pending(n_all);
  std::vector<std::vector<NodeIndex>> waiting(n_all);
  std::vector<NodeIndex> ups;
  for (NodeIndex n : members) {
    if (hit[n]) continue;
    const NodeState& s = at(n);
    const auto& specs = s.type->spec.inputs;
    ups.clear();
    for (std::size_t i = 0; i < s.inputs.size(); ++i) {
      const auto& b = s.inputs[i];
      if (links_upstream(s, i) && !specs[i].lazy && member[b.upstream])
        ups.push_back(b.upstream);
    }
    std::sort(ups.begin(), ups.end());
    ups.erase(std::unique(ups.begin(), ups.end()), ups.end());
    pending[n].store(static_cast<int>(ups.size()), std::memory_order_relaxed);
    for (NodeIndex u : ups) waiting[u].push_back(n);
  }

  tbb::task_group group;
  struct Spawner {
    Evaluation& e;
    tbb::task_group& group;
    std::vector<std::atomic<int>>& pending;
    std::vector<std::vector<NodeIndex>>& waiting;
    void operator()(NodeIndex n) const {
      group.run([this, n] {
        e.run_once(n);
        for (NodeIndex d : waiting[n])
          if (pending[d].fetch_sub(1, std::memory_order_acq_rel) == 1) (*this)(d);
      });
    }
  } spawn{*this, group, pending, waiting};
  for (NodeIndex n : members)
    if (pending[n].load(std::memory_order_relaxed) == 0) spawn(n);
  group.wait();
}

}  // namespace detail

Session::Session(const Registry& registry) : state_(std::make_unique<State>(registry)) {}
Session::~Session() = default;

std::size_t Session::cache_entries() const {
  std::lock_guard lock(state_->cache_mutex);
  return state_->cache.size();
}

void Session::clear_cache() {
  std::lock_guard lock(state_->cache_mutex);
  state_->cache.clear();
  state_->latest_states.clear();
  state_->unsaved_seconds.clear();
  std::lock_guard scratch_lock(state_->scratch_mutex);
  state_->scratch.clear();
}

namespace {

// Over frames a node's status is the most telling one it had.
int severity(NodeStatus s) {
  switch (s) {
    case NodeStatus::pruned: return 0;
    case NodeStatus::cached: return 1;
    case NodeStatus::ran: return 2;
    case NodeStatus::skipped: return 3;
    case NodeStatus::failed: return 4;
  }
  return 0;
}

void merge(NodeReport& into, NodeReport&& frame) {
  if (severity(frame.status) > severity(into.status)) {
    into.status = frame.status;
    into.error = std::move(frame.error);
  }
  into.seconds += frame.seconds;
  into.compute_seconds += frame.compute_seconds;
  into.runs += frame.runs;
  into.memory_hits += frame.memory_hits;
  into.disk_hits += frame.disk_hits;
  for (auto& w : frame.warnings)
    if (std::find(into.warnings.begin(), into.warnings.end(), w) == into.warnings.end())
      into.warnings.push_back(std::move(w));
}

}  // namespace

EvalResult Session::evaluate(const Graph& graph, const EvalOptions& options) {
  auto start = std::chrono::steady_clock::now();
  std::vector<ResolvedOutput> targets;
  try {
    targets = GraphView(graph, state_->registry).outputs(options.targets);
  } catch (const Error& e) {
    throw Error(std::string("--target: ") + e.what());
  }
  State& st = *state_;
  FrameTime time = detail::graph_time(graph);
  const FrameRange range = options.frames ? *options.frames : FrameRange{time.start, time.start};
  if (range.first > range.last)
    throw Error("frames " + std::to_string(range.first) + "-" + std::to_string(range.last) +
                ": the first frame is after the last");
  if (range.first < -kMaxFrame || range.last > kMaxFrame)
    throw Error("frames " + std::to_string(range.first) + "-" + std::to_string(range.last) +
                ": frame numbers lie between " + std::to_string(-kMaxFrame) + " and " + std::to_string(kMaxFrame));
  if (range.first < time.start)
    throw Error("frame " + std::to_string(range.first) + " is before the graph's start frame " +
                std::to_string(time.start));
  time.first = range.first;
  time.last = range.last;

  EvalResult result;
  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  tbb::task_arena arena(threads);
  const int count = range.last - range.first + 1;
  for (int frame = range.first; frame <= range.last; ++frame) {
    if (options.cancel && options.cancel->load()) break;
    if (options.observer && count > 1) options.observer->frame_started(frame, frame - range.first + 1, count);
    ++st.evaluations;
    ++st.generation;
    time.frame = frame;
    detail::Evaluation e(st, graph, options, time);
    e.build();

    std::vector<detail::NodeIndex> roots;
    if (targets.empty()) {
      for (std::size_t i = 0; i < e.nodes.size(); ++i)
        if (e.nodes[i]->type->spec.sink) roots.push_back(i);
    } else {
      for (const auto& [name, t] : targets) roots.push_back(e.index.at(t.node));
    }
    arena.execute([&] { e.execute(roots); });

    bool failed = false;
    for (auto& sp : e.nodes) {  // e.nodes is in id order
      failed = failed || sp->report.status == NodeStatus::failed || sp->report.status == NodeStatus::skipped;
      merge(result.nodes[sp->node->id], std::move(sp->report));
    }
    result.outputs.clear();  // the targets' values at the latest frame
    for (const auto& [name, t] : targets) {
      const detail::NodeState& s = e.at(e.index.at(t.node));
      if (!s.ok) continue;
      if (t.output.empty()) {
        result.outputs[name] = s.outputs;
      } else {
        result.outputs[name] = {
            s.outputs[static_cast<std::size_t>(s.type->spec.output_index(t.output))]};
      }
      if (count > 1) result.outputs_per_frame[name].push_back(result.outputs[name]);
    }
    if (!e.cancelled()) ++result.frames;
    detail::evict(st, options.state_memory_budget);
    if (failed) break;  // later frames would fail alike, or build on a failed state
  }
  {
    // Finished sequence sinks have closed their files at the last frame; the
    // state of an unfinished one is destroyed here and removes its file.
    std::lock_guard lock(st.sequence_mutex);
    st.sequences.clear();
  }
  result.cancelled = options.cancel && options.cancel->load();
  result.total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace loom
