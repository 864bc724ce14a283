#include "evaluation_controller.hpp"

#include <chrono>

namespace loom::editor {

namespace {

// The most telling status first, as the engine's report over frames.
int severity(NodeStatus s) {
  switch (s) {
    case NodeStatus::failed:
      return 4;
    case NodeStatus::skipped:
      return 3;
    case NodeStatus::ran:
      return 2;
    case NodeStatus::cached:
      return 1;
    case NodeStatus::pruned:
      return 0;
  }
  return 0;
}

// A group instance's status: its inner nodes' most telling one, their times
// summed, the first failure's message naming the inner node.
NodeReport instance_report(const EvalResult& result, const std::vector<std::string>& inner) {
  NodeReport sum;
  for (const auto& id : inner) {
    auto it = result.nodes.find(id);
    if (it == result.nodes.end()) continue;
    const NodeReport& r = it->second;
    if (severity(r.status) > severity(sum.status)) {
      sum.status = r.status;
      sum.error = r.error.empty() ? std::string() : id + ": " + r.error;
    }
    sum.seconds += r.seconds;
    sum.compute_seconds += r.compute_seconds;
    sum.runs += r.runs;
    for (const auto& w : r.warnings) sum.warnings.push_back(id + ": " + w);
  }
  return sum;
}

// Whether the view can name the target (a node deleted while a request
// was queued cannot).
bool resolves(const GraphView& view, const Target& t) {
  try {
    view.outputs(t.output.empty() ? t.node : t.node + "." + t.output);
    return true;
  } catch (const Error&) {
    return false;
  }
}

// The preview's targets: NODE.OUTPUT for every output of every node of the
// top graph and of the level `prefix` names (nodes and group instances whose
// path is PREFIX + an id), sinks left out: nothing is written.
std::vector<Target> preview_targets(const GraphView& view, const std::string& prefix) {
  auto directly_under = [](const std::string& path, const std::string& p) {
    return path.size() > p.size() && path.compare(0, p.size(), p) == 0 && path.find('.', p.size()) == std::string::npos;
  };
  auto at_level = [&](const std::string& path) {
    return directly_under(path, "") || (!prefix.empty() && directly_under(path, prefix));
  };
  std::vector<std::string> ids;
  for (const auto& [id, node] : view.graph().nodes)
    if (at_level(id)) ids.push_back(id);
  for (const auto& [id, instance] : view.graph().instances)
    if (at_level(id)) ids.push_back(id);
  std::vector<Target> targets;
  for (const auto& id : ids) {
    const NodeSpec& spec = view.type(id).spec;
    if (spec.sink) continue;
    for (const auto& o : spec.outputs) targets.push_back({id, o.name});
  }
  return targets;
}

}  // namespace

const NodeReport* Evaluation::report(const std::string& node) const {
  if (auto it = result.nodes.find(node); it != result.nodes.end()) return &it->second;
  auto it = instance_reports.find(node);
  return it == instance_reports.end() ? nullptr : &it->second;
}

Value Evaluation::output(const std::string& node, const std::string& output) const {
  if (!view || !view->has(node)) return {};
  try {
    for (const ResolvedOutput& r : view->outputs(node + "." + output)) {
      auto it = result.outputs.find(r.name);
      if (it != result.outputs.end() && it->second.size() == 1) return it->second[0];
    }
  } catch (const Error&) {
    // Not an output of that node (the document changed since): no value.
  }
  return {};
}

// Collects node progress and partial values from the engine's worker threads.
class EvaluationController::Progress : public Observer {
 public:
  void node_started(const std::string& id, const std::string&) override {
    std::lock_guard<std::mutex> lock(mutex_);
    nodes_[id] = {true, 0, {}, {}};
    started_[id] = std::chrono::steady_clock::now();
  }
  // Every node's partials are wanted: only the viewed node's are shown, but
  // the viewer may switch to another while it runs. Making one (PathTrace:
  // the means of a pass) costs little next to the pass.
  bool wants_partial(const std::string&) const override { return true; }
  void node_partial(const std::string& id, const std::string& output, const Value& value,
                    const PartialInfo& info) override {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto since = started_.count(id) ? started_[id] : std::chrono::steady_clock::now();
    partials_[id + "." + output] = {revision_, value, info.done, info.total, std::string(info.unit),
                                    info.relative_error,
                                    std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count(),
                                    ++serial_};
  }
  std::optional<Partial> partial(const std::string& name) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = partials_.find(name);
    if (it == partials_.end()) return std::nullopt;
    return it->second;
  }
  bool any_partial() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return !partials_.empty();
  }
  // A new run: the previous run's partials are of another graph.
  void begin(std::uint64_t revision) {
    std::lock_guard<std::mutex> lock(mutex_);
    revision_ = revision;
    partials_.clear();
    started_.clear();
  }
  void node_progress(const std::string& id, double fraction, const std::string& label) override {
    std::lock_guard<std::mutex> lock(mutex_);
    nodes_[id] = {true, fraction, label, {}};
  }
  void node_finished(const std::string& id, const NodeReport& report) override {
    std::lock_guard<std::mutex> lock(mutex_);
    nodes_[id] = {false, 1, {}, report};
  }
  void reset() {
    std::lock_guard<std::mutex> lock(mutex_);
    nodes_.clear();
  }
  std::map<std::string, LiveNode> snapshot() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return nodes_;
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, LiveNode> nodes_;
  std::map<std::string, std::chrono::steady_clock::time_point> started_;
  std::map<std::string, Partial> partials_;  // by "ID.OUTPUT"
  std::uint64_t revision_ = 0, serial_ = 0;
};

EvaluationController::EvaluationController(const Registry& registry, int threads)
    : registry_(registry), threads_(threads), session_(registry), progress_(std::make_unique<Progress>()) {
  worker_ = std::thread([this] { work(); });
}

EvaluationController::~EvaluationController() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    pending_.reset();
  }
  cancel_ = true;
  wake_.notify_all();
  worker_.join();
}

void EvaluationController::submit(EvalRequest request, bool cancel_running) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_ = std::move(request);
    if (running_ && cancel_running) cancel_ = true;
  }
  wake_.notify_all();
}

void EvaluationController::cancel() {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.reset();
  if (running_) cancel_ = true;
}

std::optional<std::shared_ptr<const Evaluation>> EvaluationController::take_finished() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!fresh_) return std::nullopt;
  fresh_ = false;
  return latest_;
}

std::shared_ptr<const Evaluation> EvaluationController::latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

std::map<std::string, LiveNode> EvaluationController::live() const { return progress_->snapshot(); }

bool EvaluationController::refining() const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!running_) return false;
  }
  return progress_->any_partial();
}

std::optional<Partial> EvaluationController::partial(const std::string& node, const std::string& output) const {
  return progress_->partial(node + "." + output);
}

bool EvaluationController::busy() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return running_ || pending_.has_value();
}

void EvaluationController::wait_idle() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return !running_ && !pending_; });
}

void EvaluationController::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || pending_.has_value(); });
    if (stop_) return;
    EvalRequest request = std::move(*pending_);
    pending_.reset();
    running_ = true;
    cancel_ = false;
    lock.unlock();
    std::shared_ptr<Evaluation> done = run(request);
    lock.lock();
    running_ = false;
    // A cancelled run was superseded: the next request's result replaces it.
    if (!done->result.cancelled || !pending_) {
      latest_ = std::move(done);
      fresh_ = true;
    }
    if (!pending_) idle_.notify_all();
  }
}

std::shared_ptr<Evaluation> EvaluationController::run(const EvalRequest& request) {
  auto eval = std::make_shared<Evaluation>();
  eval->revision = request.revision;
  eval->preview = request.preview;
  const auto start = std::chrono::steady_clock::now();
  progress_->reset();
  progress_->begin(request.revision);
  try {
    auto graph = std::make_shared<Graph>(parse_graph(request.document, request.file));
    validate_graph(*graph, registry_);
    eval->graph = graph;
    eval->view = std::make_shared<GraphView>(*graph, registry_);
    const std::vector<Target> asked =
        request.preview ? preview_targets(*eval->view, *request.preview) : request.targets;
    for (const Target& t : asked)
      if (resolves(*eval->view, t)) eval->targets.push_back(t);
    if ((request.preview || !request.targets.empty()) && eval->targets.empty()) {
      eval->seconds = 0;
      return eval;
    }
    EvalOptions options;
    options.targets = eval->targets;
    options.threads = threads_;
    options.output_dir = request.output_dir.empty() ? graph->dir() : request.output_dir;
    options.observer = progress_.get();
    options.cancel = &cancel_;
    options.frames = request.frames;
    if (request.frames) eval->frame = request.frames->last;
    eval->result = session_.evaluate(*graph, options);
    for (const auto& [path, instance] : graph->instances)
      eval->instance_reports[path] = instance_report(eval->result, eval->view->inner_nodes(path));
    // Also after a cancelled run: what it stepped is kept.
    eval->frames_of = request.frames_of;
    if (graph->time && graph->nodes.count(request.frames_of))
      eval->cached_frames =
          session_.cached_frames(*graph, request.frames_of, {graph->time->start, graph->time->end}, options);
  } catch (const GraphError& e) {
    for (const GraphIssue& issue : e.issues()) eval->issues.push_back(locate_issue(issue));
  } catch (const std::exception& e) {
    eval->error = e.what();
  }
  progress_->reset();
  eval->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return eval;
}

}  // namespace loom::editor
