#include "loom/evaluator.hpp"

#include <algorithm>
#include <deque>
#include <mutex>
#include <unordered_map>

#include <thread>

#include <tbb/info.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "input_check.hpp"
#include "literal.hpp"
#include "progress_gate.hpp"

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
  auto dot = text.find('.');
  if (dot == std::string::npos) return {text, ""};
  return {text.substr(0, dot), text.substr(dot + 1)};
}

bool EvalResult::ok() const {
  for (const auto& [id, r] : nodes)
    if (r.status == NodeStatus::failed || r.status == NodeStatus::skipped) return false;
  return !cancelled;
}

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

namespace {

// Thrown into a node body when a lazily fetched input's upstream failed.
struct UpstreamFailed : Error {
  using Error::Error;
};

struct Evaluation;

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

  bool cancelled() const { return options.cancel && options.cancel->load(std::memory_order_relaxed); }

  bool cache_has(std::uint64_t hash) {
    std::lock_guard lock(session.cache_mutex);
    return session.cache.count(hash) != 0;
  }

  void build();
  void execute(const std::vector<int>& roots);
  // Runs node n unless another thread does or did. Contention only happens when
  // a lazy fetch and the scheduler reach the same node; the loser waits. The
  // winner never waits on the loser (node bodies run isolated, and the graph is
  // acyclic), so waiting cannot deadlock.
  void run_once(int n) {
    NodeState& s = *nodes[static_cast<std::size_t>(n)];
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

// Per-node services for the node body.
class Host final : public NodeHost {
 public:
  Host(Evaluation& e, NodeState& s) : e_(e), s_(s) {}

  Value fetch_input(int i) override {
    const auto& b = s_.inputs[static_cast<std::size_t>(i)];
    if (b.kind == NodeState::Binding::literal) return b.literal_value;
    NodeState& up = *e_.nodes[static_cast<std::size_t>(b.upstream)];
    if (!up.done.load(std::memory_order_acquire)) e_.execute({b.upstream});
    if (!up.ok)
      throw UpstreamFailed("input \"" + s_.type->spec.inputs[static_cast<std::size_t>(i)].name +
                           "\": node \"" + up.node->id + "\" " + to_string(up.report.status));
    const InputSpec& spec = s_.type->spec.inputs[static_cast<std::size_t>(i)];
    detail::check_input_value(spec, up.outputs[static_cast<std::size_t>(b.output)]);
    if (spec.role == InputRole::value) return up.outputs[static_cast<std::size_t>(b.output)];
    // A resolved path is a new value: the host keeps it alive for the run,
    // since in.get returns a reference into it.
    Value path = detail::resolve_path_value(spec, up.outputs[static_cast<std::size_t>(b.output)], e_.graph_dir,
                                            e_.options.output_dir, e_.options.allow_outside_output);
    std::lock_guard lock(mutex_);
    return resolved_paths_.emplace_back(std::move(path));
  }
  bool input_set(int i) const override {
    return s_.inputs[static_cast<std::size_t>(i)].kind != NodeState::Binding::unset;
  }
  void report_progress(double fraction, std::string_view label) override {
    progress_.offer(fraction, label, [&](double f, const std::string& l) {
      if (e_.options.observer) e_.options.observer->node_progress(s_.node->id, f, l);
    });
  }
  void report(bool warning, std::string text) override {
    if (warning) {
      std::lock_guard lock(mutex_);
      s_.report.warnings.push_back(text);
    }
    if (e_.options.observer) e_.options.observer->node_message(s_.node->id, warning, text);
  }
  bool cancelled() const override { return e_.cancelled(); }
  std::shared_ptr<void> scratch(std::uint64_t key,
                                const std::function<std::shared_ptr<void>()>& make) override {
    auto& session = e_.session;
    {
      std::lock_guard lock(session.scratch_mutex);
      auto& list = session.scratch[s_.node->id];
      for (auto it = list.begin(); it != list.end(); ++it)
        if (it->first == key) {
          auto entry = *it;
          list.erase(it);
          list.push_front(entry);
          return entry.second;
        }
    }
    std::shared_ptr<void> made = make();  // outside the lock: may be slow
    std::lock_guard lock(session.scratch_mutex);
    auto& list = session.scratch[s_.node->id];
    list.emplace_front(key, made);
    if (list.size() > Session::State::kScratchPerNode) list.pop_back();
    return made;
  }

 private:
  Evaluation& e_;
  NodeState& s_;
  std::mutex mutex_;
  std::deque<Value> resolved_paths_;
  detail::ProgressGate progress_;
};

void hash_file_stamp(Hasher& h, const std::string& path) {
  std::error_code ec;
  auto size = std::filesystem::file_size(path, ec);
  h.pod(ec ? std::uint64_t(-1) : static_cast<std::uint64_t>(size));
  auto time = std::filesystem::last_write_time(path, ec);
  h.pod(ec ? std::int64_t(-1) : static_cast<std::int64_t>(time.time_since_epoch().count()));
}

void Evaluation::build() {
  nodes.reserve(graph.nodes.size());
  for (const auto& [id, n] : graph.nodes) {
    index.emplace(id, static_cast<int>(nodes.size()));
    auto s = std::make_unique<NodeState>();
    s->node = &n;
    s->type = session.registry.find(n.type);
    if (!s->type) throw Error("node \"" + id + "\": unknown type " + n.type + " (graph not validated)");
    nodes.push_back(std::move(s));
  }
  // Bindings, links and topological order (iterative post-order DFS).
  for (auto& sp : nodes) {
    NodeState& s = *sp;
    const auto& specs = s.type->spec.inputs;
    s.inputs.resize(specs.size());
    for (std::size_t i = 0; i < specs.size(); ++i) {
      const InputSpec& spec = specs[i];
      auto& b = s.inputs[i];
      auto it = s.node->inputs.find(spec.name);
      if (it != s.node->inputs.end() && it->second.link) {
        b.kind = NodeState::Binding::link;
        b.upstream = index.at(it->second.link->node);
        const NodeState& up = *nodes[static_cast<std::size_t>(b.upstream)];
        b.output = up.type->spec.output_index(it->second.link->output);
        continue;
      }
      const json* literal = it != s.node->inputs.end() ? &it->second.literal
                            : spec.default_value.is_null() ? nullptr
                                                           : &spec.default_value;
      if (!literal) continue;  // optional and unset
      b.kind = NodeState::Binding::literal;
      b.literal_value = detail::literal_value(spec, *literal);
      try {
        b.literal_value = detail::resolve_path_value(spec, b.literal_value, graph_dir, options.output_dir,
                                                     options.allow_outside_output);
      } catch (const Error& e) {
        throw Error("node \"" + s.node->id + "\": " + e.what());
      }
    }
  }
  std::vector<int> order;
  std::vector<char> mark(nodes.size(), 0);
  for (int root = 0; root < static_cast<int>(nodes.size()); ++root) {
    if (mark[static_cast<std::size_t>(root)]) continue;
    std::vector<std::pair<int, std::size_t>> stack{{root, 0}};
    mark[static_cast<std::size_t>(root)] = 1;
    while (!stack.empty()) {
      auto& [n, next] = stack.back();
      const auto& ins = nodes[static_cast<std::size_t>(n)]->inputs;
      if (next == ins.size()) {
        order.push_back(n);
        stack.pop_back();
        continue;
      }
      const auto& b = ins[next++];
      if (b.kind == NodeState::Binding::link && !mark[static_cast<std::size_t>(b.upstream)]) {
        mark[static_cast<std::size_t>(b.upstream)] = 1;
        stack.emplace_back(b.upstream, 0);
      }
    }
  }
  const std::uint64_t run_salt = Hasher().pod(session.evaluations).str("nondeterministic").digest();
  for (int n : order) {
    NodeState& s = *nodes[static_cast<std::size_t>(n)];
    const NodeSpec& spec = s.type->spec;
    Hasher h;
    // The node's seed enters the hash: any node may draw from ctx.rng(), so two
    // nodes with equal inputs but different ids (or graph seeds) may differ.
    s.seed = Hasher(graph.seed).str(s.node->id).digest();
    h.str(spec.name).pod(spec.version).pod(s.seed);
    for (std::size_t i = 0; i < s.inputs.size(); ++i) {
      const auto& b = s.inputs[i];
      h.str(spec.inputs[i].name).pod(static_cast<int>(b.kind));
      if (b.kind == NodeState::Binding::literal) {
        hash_json(h, b.literal_value.to_json());
        if (spec.inputs[i].role == InputRole::input_file)
          hash_file_stamp(h, b.literal_value.as<std::string>());
      } else if (b.kind == NodeState::Binding::link) {
        h.pod(nodes[static_cast<std::size_t>(b.upstream)]->hash).pod(b.output);
      }
    }
    if (spec.nondeterministic) h.pod(run_salt);
    s.hash = h.digest();
    s.cacheable = !spec.sink && !spec.nondeterministic;
  }
}

void Evaluation::execute(const std::vector<int>& roots) {
  // The closure of the roots over non-lazy links, stopping at finished nodes
  // and at cache hits (a hit needs none of its inputs).
  const std::size_t n_all = nodes.size();
  std::vector<char> member(n_all, 0), hit(n_all, 0);
  std::vector<int> members, stack;
  auto visit = [&](int n) {
    if (member[static_cast<std::size_t>(n)] || nodes[static_cast<std::size_t>(n)]->done.load(std::memory_order_acquire))
      return;
    member[static_cast<std::size_t>(n)] = 1;
    stack.push_back(n);
  };
  for (int r : roots) visit(r);
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    members.push_back(n);
    NodeState& s = *nodes[static_cast<std::size_t>(n)];
    if (s.cacheable && cache_has(s.hash)) {
      hit[static_cast<std::size_t>(n)] = 1;
      continue;
    }
    const auto& specs = s.type->spec.inputs;
    for (std::size_t i = 0; i < s.inputs.size(); ++i)
      if (s.inputs[i].kind == NodeState::Binding::link && !specs[i].lazy) visit(s.inputs[i].upstream);
  }
  // For each member, how many distinct member inputs it waits on, and who
  // waits on whom.
  std::vector<std::atomic<int>> pending(n_all);
  std::vector<std::vector<int>> waiting(n_all);
  std::vector<int> ups;
  for (int n : members) {
    if (hit[static_cast<std::size_t>(n)]) continue;
    const NodeState& s = *nodes[static_cast<std::size_t>(n)];
    const auto& specs = s.type->spec.inputs;
    ups.clear();
    for (std::size_t i = 0; i < s.inputs.size(); ++i) {
      const auto& b = s.inputs[i];
      if (b.kind == NodeState::Binding::link && !specs[i].lazy && member[static_cast<std::size_t>(b.upstream)])
        ups.push_back(b.upstream);
    }
    std::sort(ups.begin(), ups.end());
    ups.erase(std::unique(ups.begin(), ups.end()), ups.end());
    pending[static_cast<std::size_t>(n)].store(static_cast<int>(ups.size()), std::memory_order_relaxed);
    for (int u : ups) waiting[static_cast<std::size_t>(u)].push_back(n);
  }

  tbb::task_group group;
  struct Spawner {
    Evaluation& e;
    tbb::task_group& group;
    std::vector<std::atomic<int>>& pending;
    std::vector<std::vector<int>>& waiting;
    void operator()(int n) const {
      group.run([this, n] {
        e.run_once(n);
        for (int d : waiting[static_cast<std::size_t>(n)])
          if (pending[static_cast<std::size_t>(d)].fetch_sub(1, std::memory_order_acq_rel) == 1) (*this)(d);
      });
    }
  } spawn{*this, group, pending, waiting};
  for (int n : members)
    if (pending[static_cast<std::size_t>(n)].load(std::memory_order_relaxed) == 0) spawn(n);
  group.wait();
}

void Evaluation::run_node(int n) {
  NodeState& s = *nodes[static_cast<std::size_t>(n)];
  const NodeSpec& spec = s.type->spec;
  if (cancelled()) {
    s.report.status = NodeStatus::skipped;
    s.report.error = "cancelled";
    return finish(s);
  }
  if (s.cacheable) {
    std::lock_guard lock(session.cache_mutex);
    auto it = session.cache.find(s.hash);
    if (it != session.cache.end()) {
      it->second.generation = session.generation;
      s.outputs = it->second.outputs;
      s.ok = true;
      s.report.status = NodeStatus::cached;
    }
  }
  if (s.ok) return finish(s);

  // Normally the scheduler has run every non-lazy input already; if not (a
  // lazy fetch reached this node through another path), run them now.
  std::vector<int> missing;
  for (std::size_t i = 0; i < s.inputs.size(); ++i) {
    const auto& b = s.inputs[i];
    if (b.kind == NodeState::Binding::link && !spec.inputs[i].lazy &&
        !nodes[static_cast<std::size_t>(b.upstream)]->done.load(std::memory_order_acquire))
      missing.push_back(b.upstream);
  }
  if (!missing.empty()) execute(missing);
  for (std::size_t i = 0; i < s.inputs.size(); ++i) {
    const auto& b = s.inputs[i];
    if (b.kind != NodeState::Binding::link || spec.inputs[i].lazy) continue;
    const NodeState& up = *nodes[static_cast<std::size_t>(b.upstream)];
    if (!up.ok) {
      s.report.status = NodeStatus::skipped;
      s.report.error = "input \"" + spec.inputs[i].name + "\": node \"" + up.node->id + "\" " +
                       to_string(up.report.status);
      return finish(s);
    }
  }

  if (options.observer) options.observer->node_started(s.node->id, spec.name);
  Host host(*this, s);
  Inputs in(spec, host);
  Outputs out(spec);
  Context ctx(host, s.node->id, s.seed, graph_dir,
              options.output_dir);
  auto start = std::chrono::steady_clock::now();
  try {
    // Every non-lazy linked value is checked before the body runs, whether or
    // not the body reads it (fetch_input checks ranges, choices and paths).
    for (std::size_t i = 0; i < s.inputs.size(); ++i)
      if (s.inputs[i].kind == NodeState::Binding::link && !spec.inputs[i].lazy) host.fetch_input(static_cast<int>(i));
    tbb::this_task_arena::isolate([&] { s.type->run(in, out, ctx); });
    for (std::size_t o = 0; o < spec.outputs.size(); ++o)
      if (!out.values()[o])
        throw Error("node did not set its output \"" + spec.outputs[o].name + "\" (a bug in " +
                    spec.name + ")");
    s.outputs = std::move(out.values());
    s.ok = true;
    s.report.status = NodeStatus::ran;
  } catch (const UpstreamFailed& e) {
    s.report.status = NodeStatus::skipped;
    s.report.error = e.what();
  } catch (const std::exception& e) {
    s.report.status = NodeStatus::failed;
    s.report.error = e.what();
  } catch (...) {
    s.report.status = NodeStatus::failed;
    s.report.error = "unknown exception";
  }
  s.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (s.ok && s.cacheable && !cancelled()) {
    std::lock_guard lock(session.cache_mutex);
    session.cache[s.hash] = {s.outputs, session.generation};
  }
  finish(s);
}

}  // namespace

Session::Session(const Registry& registry) : state_(std::make_unique<State>(registry)) {}
Session::~Session() = default;

std::size_t Session::cache_entries() const {
  std::lock_guard lock(state_->cache_mutex);
  return state_->cache.size();
}

void Session::clear_cache() {
  std::lock_guard lock(state_->cache_mutex);
  state_->cache.clear();
  std::lock_guard scratch_lock(state_->scratch_mutex);
  state_->scratch.clear();
}

EvalResult Session::evaluate(const Graph& graph, const EvalOptions& options) {
  auto start = std::chrono::steady_clock::now();
  State& st = *state_;
  ++st.evaluations;
  ++st.generation;
  Evaluation e(st, graph, options);
  e.build();

  std::vector<int> roots;
  if (options.targets.empty()) {
    for (std::size_t i = 0; i < e.nodes.size(); ++i)
      if (e.nodes[i]->type->spec.sink) roots.push_back(static_cast<int>(i));
  } else {
    for (const Target& t : options.targets) {
      auto it = e.index.find(t.node);
      if (it == e.index.end()) throw Error("--target names unknown node \"" + t.node + "\"");
      const NodeState& s = *e.nodes[static_cast<std::size_t>(it->second)];
      if (!t.output.empty() && s.type->spec.output_index(t.output) < 0)
        throw Error("--target: node \"" + t.node + "\" (" + s.type->spec.name +
                    ") has no output \"" + t.output + "\"");
      roots.push_back(it->second);
    }
  }

  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  tbb::task_arena arena(threads);
  arena.execute([&] { e.execute(roots); });

  EvalResult result;
  for (auto& sp : e.nodes)  // e.nodes is in id order: each insertion is at the end
    result.nodes.emplace_hint(result.nodes.end(), sp->node->id, std::move(sp->report));
  for (const Target& t : options.targets) {
    const NodeState& s = *e.nodes[static_cast<std::size_t>(e.index.at(t.node))];
    if (!s.ok) continue;
    if (t.output.empty()) {
      result.outputs[t.node] = s.outputs;
    } else {
      result.outputs[t.node + "." + t.output] = {
          s.outputs[static_cast<std::size_t>(s.type->spec.output_index(t.output))]};
    }
  }
  result.cancelled = e.cancelled();
  {  // keep what the last two evaluations used
    std::lock_guard lock(st.cache_mutex);
    for (auto it = st.cache.begin(); it != st.cache.end();)
      it = it->second.generation + 1 < st.generation ? st.cache.erase(it) : std::next(it);
  }
  result.total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace loom
