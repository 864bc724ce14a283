#include "evaluation_controller.hpp"

#include <chrono>

namespace loom::editor {

// Collects node progress from the engine's worker threads.
class EvaluationController::Progress : public Observer {
 public:
  void node_started(const std::string& id, const std::string&) override {
    std::lock_guard<std::mutex> lock(mutex_);
    nodes_[id] = {true, 0, {}};
  }
  void node_progress(const std::string& id, double fraction, const std::string& label) override {
    std::lock_guard<std::mutex> lock(mutex_);
    nodes_[id] = {true, fraction, label};
  }
  void node_finished(const std::string& id, const NodeReport&) override {
    std::lock_guard<std::mutex> lock(mutex_);
    nodes_.erase(id);
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
  const auto start = std::chrono::steady_clock::now();
  progress_->reset();
  try {
    Graph graph = parse_graph(request.document, request.file);
    validate_graph(graph, registry_);
    // A target naming a node that is gone (deleted while queued) is dropped.
    for (const Target& t : request.targets)
      if (graph.nodes.count(t.node)) eval->targets.push_back(t);
    if (!request.targets.empty() && eval->targets.empty()) {
      eval->seconds = 0;
      return eval;
    }
    EvalOptions options;
    options.targets = eval->targets;
    options.threads = threads_;
    options.output_dir = request.output_dir.empty() ? graph.dir() : request.output_dir;
    options.observer = progress_.get();
    options.cancel = &cancel_;
    options.frames = request.frames;
    if (request.frames) eval->frame = request.frames->last;
    eval->result = session_.evaluate(graph, options);
    // Also after a cancelled run: what it stepped is kept.
    eval->frames_of = request.frames_of;
    if (graph.time && graph.nodes.count(request.frames_of))
      eval->cached_frames =
          session_.cached_frames(graph, request.frames_of, {graph.time->start, graph.time->end}, options);
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
