// loom.Session: one `loom run` process kept alive. run() evaluates on a
// thread of its own while the calling thread, without the GIL, waits for it:
// it wakes every 50 ms to hand progress to the Python callback and to check
// for Ctrl-C (KeyboardInterrupt cancels the running nodes, as in the runner,
// and is raised at once: see SessionCore::Running).
#include "session.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "loom/disk_cache.hpp"
#include "loom/graph_view.hpp"
#include "held_value.hpp"
#include "python_nodes.hpp"
#include "values.hpp"
#include "world.hpp"

namespace loom::python {

namespace {

struct Event {
  std::string kind;  // "started", "progress", "message", "finished", "frame", "partial"
  std::string node;
  double fraction = 0;
  std::string text;
  Value value;  // "partial": the value so far
};

// Collects what the engine reports from its threads; the caller's thread
// drains it into Python.
class QueueObserver : public Observer {
 public:
  explicit QueueObserver(bool partials) : partials(partials) {}
  const bool partials;  // a callback is there to take them
  std::mutex mutex;
  std::condition_variable wake;
  std::deque<Event> events;
  bool done = false;

  void push(Event e) {
    std::lock_guard<std::mutex> lock(mutex);
    const bool latest_only = e.kind == "progress" || e.kind == "partial";
    if (latest_only && !events.empty() && events.back().kind == e.kind && events.back().node == e.node &&
        events.back().text == e.text)
      events.back() = std::move(e);  // only the latest progress (or partial) of a node is worth showing
    else
      events.push_back(std::move(e));
  }
  void node_started(const std::string& id, const std::string& type) override { push({"started", id, 0, type, {}}); }
  void node_progress(const std::string& id, double f, const std::string& label) override {
    push({"progress", id, f, label, {}});
  }
  void node_message(const std::string& id, bool warning, const std::string& text) override {
    push({warning ? "warning" : "message", id, 0, text, {}});
  }
  void node_finished(const std::string& id, const NodeReport& r) override {
    push({"finished", id, r.seconds, to_string(r.status), {}});
  }
  void frame_started(int frame, int index, int count) override {
    push({"frame", std::to_string(frame), double(index) / count, "", {}});
  }
  bool wants_partial(const std::string&) const override { return partials; }
  void node_partial(const std::string& id, const std::string& output, const Value& value,
                    const PartialInfo& info) override {
    push({"partial", id, info.total > 0 ? info.done / info.total : 0, output, value});
  }
};

py::object partial_value(const Value& v) {
  std::lock_guard<std::recursive_mutex> lock(world().mutex);  // as the outputs are converted
  return to_python(v);
}

py::dict report_to_python(const NodeReport& r) {
  py::dict d;
  d["status"] = to_string(r.status);
  d["seconds"] = r.seconds;
  d["compute_seconds"] = r.compute_seconds;
  d["runs"] = r.runs;
  d["memory_hits"] = r.memory_hits;
  d["disk_hits"] = r.disk_hits;
  d["error"] = r.error;
  d["warnings"] = r.warnings;
  return d;
}

}  // namespace

SessionCore::SessionCore(int threads, std::optional<std::string> disk_cache, std::string output_dir,
                         bool allow_outside_output)
    : session(world().registry), threads(threads), output_dir(std::move(output_dir)),
      allow_outside_output(allow_outside_output) {
  if (disk_cache) {
    DiskCache::Options o;
    o.dir = disk_cache->empty() ? DiskCache::default_dir() : std::filesystem::path(*disk_cache);
    disk.emplace(o);
  }
}

namespace {

// The run's outputs by "ID.OUTPUT", as the engine names them (one value, or
// over several frames the list of its values), and each node's report.
py::dict result_to_python(const Graph& prepared, const EvalResult& result) {
  py::dict out;
  py::dict outputs;
  {
    std::lock_guard<std::recursive_mutex> lock(world().mutex);
    for (const auto& [name, values] : named_outputs_per_frame(GraphView(prepared, world().registry), result)) {
      if (values.size() == 1) {
        outputs[py::str(name)] = to_python(values[0]);
        continue;
      }
      py::list frames;
      for (const Value& v : values) frames.append(to_python(v));
      outputs[py::str(name)] = frames;
    }
  }
  py::dict nodes;
  for (const auto& [id, r] : result.nodes)
    if (prepared.nodes.at(id).type != "python.HeldValue") nodes[py::str(id)] = report_to_python(r);
  out["outputs"] = outputs;
  out["nodes"] = nodes;
  out["seconds"] = result.total_seconds;
  out["frames"] = result.frames;
  out["cancelled"] = result.cancelled;
  return out;
}

}  // namespace

// One evaluation on a thread of its own, with what it reads. A run that
// Ctrl-C interrupts is left to end its cancelled work here (a sparse
// factorization cannot be asked to stop: 0.6-1.9 s in ARAP), so that the
// KeyboardInterrupt reaches the caller at once; the session's next call
// waits for it first.
struct SessionCore::Running {
  py::object graph;  // the PreparedGraph: its held values stay alive
  EvalOptions options;
  std::atomic<bool> cancel{false};
  QueueObserver observer;
  EvalResult result;
  std::exception_ptr failure;
  ActiveRun active;
  std::thread worker;
  std::mutex joining;  // two Python threads may settle one session at once
  explicit Running(bool partials) : observer(partials) {}
  void join() {
    std::lock_guard<std::mutex> lock(joining);
    if (worker.joinable()) worker.join();
  }
};

void SessionCore::settle() {
  const std::shared_ptr<Running> run = finishing;
  if (!run) return;
  {
    py::gil_scoped_release release;  // its Python bodies may need the GIL to end
    run->join();
  }
  if (finishing == run) finishing.reset();  // with the GIL: it holds the graph's Python object
}

SessionCore::~SessionCore() {
  if (!finishing) return;
  if (PyGILState_Check())
    settle();
  else
    finishing->join();
}

py::dict SessionCore::run(const py::object& prepared_object, const std::vector<std::string>& targets,
                          std::optional<std::pair<int, int>> frames, const py::object& progress) {
  settle();
  auto run = std::make_shared<Running>(!progress.is_none());
  run->graph = prepared_object;
  const Graph& prepared = prepared_object.cast<const PreparedGraph&>().graph;
  EvalOptions& options = run->options;
  for (const auto& t : targets) options.targets.push_back(parse_target(t));
  options.threads = threads;
  options.output_dir = std::filesystem::absolute(output_dir);
  options.allow_outside_output = allow_outside_output;
  if (frames) options.frames = FrameRange{frames->first, frames->second};
  else if (prepared.time) options.frames = FrameRange{prepared.time->start, prepared.time->end};
  if (disk) options.disk_cache = &*disk;
  options.cancel = &run->cancel;
  options.observer = &run->observer;

  run->worker = std::thread([this, run = run.get(), &prepared] {
    try {
      run->result = session.evaluate(prepared, run->options);
    } catch (...) {
      run->failure = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(run->observer.mutex);
    run->observer.done = true;
    run->observer.wake.notify_all();
  });
  QueueObserver& observer = run->observer;
  for (bool done = false; !done;) {
    std::deque<Event> events;
    {
      py::gil_scoped_release release;
      std::unique_lock<std::mutex> lock(observer.mutex);
      observer.wake.wait_for(lock, std::chrono::milliseconds(50));
      events.swap(observer.events);
      done = observer.done;
    }
    try {
      if (!progress.is_none())
        for (const Event& e : events)
          progress(e.kind, e.node, e.fraction, e.text, e.value ? partial_value(e.value) : py::none());
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    } catch (py::error_already_set&) {  // Ctrl-C, or the callback raised: cancel, and raise at once
      run->cancel = true;
      interrupt_python_bodies();  // a body that never asks ctx.cancelled() stops too
      finishing = std::move(run);
      throw;
    }
  }
  {
    py::gil_scoped_release release;
    run->join();
  }
  if (run->failure) std::rethrow_exception(run->failure);
  return result_to_python(prepared, run->result);
}

void bind_session(py::module_& m) {
  py::class_<SessionCore>(m, "SessionCore")
      .def(py::init<int, std::optional<std::string>, std::string, bool>())
      .def("run", &SessionCore::run)
      .def("settle", &SessionCore::settle)
      .def("cache_entries",
           [](SessionCore& s) {
             s.settle();
             return s.session.cache_entries();
           })
      .def("clear_cache", [](SessionCore& s) {
        s.settle();
        s.session.clear_cache();
      });
}

}  // namespace loom::python
