#include "farm/jobs.hpp"

#include <signal.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <algorithm>
#include <map>
#include <optional>
#include <sstream>

#include "farm/child_process.hpp"
#include "farm/dispatch.hpp"
#include "cli/run_settings.hpp"
#include "loom/frame_pattern.hpp"
#include "loom/graph_view.hpp"

namespace loom::runner {
namespace fs = std::filesystem;

namespace {

// A task tried more than once: where each try ran and how it ended, which is
// why the next one ran ("n2 lost (its node failed; requeued by Slurm), n1 done").
void print_tries(const TaskStatus& s) {
  if (s.tries.size() < 2) return;
  std::string line;
  for (const TaskTry& t : s.tries) line += (line.empty() ? "" : ", ") + t.host + " " + t.end;
  std::printf("      tries: %s\n", line.c_str());
}

}  // namespace

int jobs_status(const JobManifest& m) {
  std::map<TaskState, int> counts;
  for (const Task& t : m.tasks) {
    const TaskStatus s = read_status(m.dir, t.id);
    ++counts[s.state];
    std::printf("%4d  %-9s %-28s attempts %d  %7.2f s  %s%s\n", t.id, task_state_text(s.state), t.name.c_str(),
                s.attempts, s.seconds, s.host.c_str(), s.message.empty() ? "" : ("  " + s.message).c_str());
    print_tries(s);
  }
  std::printf("%zu tasks: %d done, %d failed, %d cancelled, %d running, %d pending (%s)\n", m.tasks.size(),
              counts[TaskState::done], counts[TaskState::failed], counts[TaskState::cancelled],
              counts[TaskState::running], counts[TaskState::pending], m.to.c_str());
  return counts[TaskState::done] == static_cast<int>(m.tasks.size()) ? kOk : kNodeFailed;
}

bool slurm_jobs_queued(const JobManifest& m) {
  std::ifstream in(m.dir / "slurm" / "jobs");
  std::vector<std::string> argv = {"squeue", "-h", "-o", "%i", "-j"};
  std::string ids;
  for (std::string id; std::getline(in, id);)
    if (!id.empty()) ids += (ids.empty() ? "" : ",") + id;
  if (ids.empty()) return false;
  argv.push_back(ids);
  int exit = 0;
  const std::string out = capture_output(argv, &exit);
  return out.find_first_not_of(" \n") != std::string::npos;  // squeue fails on ids it forgot
}

namespace {
// The process recorded in a task's status, if it is still that task's.
bool task_process_alive(const fs::path& job, const TaskStatus& s, int id) {
  return s.pid > 0 && same_process(s.pid, s.pid_start, {"jobs", "task", job.string(), std::to_string(id)});
}
}  // namespace

bool still_running(const JobManifest& m, const TaskStatus& s, int id) {
  if (s.host == host_name()) return task_process_alive(m.dir, s, id);
  if (m.to != "slurm") return true;  // another machine's process: cannot tell
  return slurm_jobs_queued(m);
}

namespace {

// The value after `flag` in a task's arguments, every one of them.
std::vector<std::string> arguments_of(const Task& t, const std::string& flag) {
  std::vector<std::string> values;
  for (std::size_t k = 0; k + 1 < t.args.size(); ++k)
    if (t.args[k] == flag) values.push_back(t.args[k + 1]);
  return values;
}

// The files a task that ended "done" wrote, as far as the job's graph tells:
// a sweep point's point.json, the sweep tables, and each sink's literal output
// paths over the task's frames. Linked paths cannot be known: not listed.
std::vector<fs::path> expected_outputs(const Task& t, const LoadedGraph& g) {
  const auto out = arguments_of(t, "--out");
  if (out.empty()) return {};
  const fs::path dir = out.front();
  std::vector<fs::path> files;
  if (std::find(t.args.begin(), t.args.end(), "--sweep-collect") != t.args.end()) return {dir / "sweep.csv"};
  for (const std::string& list : arguments_of(t, "--sweep-points")) {
    std::istringstream points(list);
    for (std::string i; std::getline(points, i, ',');)
      files.push_back(dir / "points" / (std::string(4 - std::min<std::size_t>(4, i.size()), '0') + i) / "point.json");
    return files;
  }
  Graph graph = g.graph;
  for (const std::string& set : arguments_of(t, "--set")) set_input(graph, set);
  const GraphView view(graph, *g.registry);
  std::vector<std::string> nodes;
  for (const std::string& target : arguments_of(t, "--target")) nodes.push_back(parse_target(target).node);
  if (nodes.empty()) nodes = view.sinks();
  const auto frames = arguments_of(t, "--frames");
  const std::optional<FrameRange> range = frames.empty() ? std::nullopt : parse_frame_range(frames.front());
  for (const std::string& id : nodes) {
    auto n = graph.nodes.find(id);
    if (n == graph.nodes.end() || !view.has(id)) continue;
    for (const InputSpec& spec : view.type(id).spec.inputs) {
      auto b = n->second.inputs.find(spec.name);
      if (spec.role != InputRole::output_file || b == n->second.inputs.end() || b->second.link ||
          !b->second.literal.is_string())
        continue;
      const std::string path = b->second.literal;
      if (!range && path.find('{') != std::string::npos) continue;  // which frame it names is the evaluator's
      for (long f = range ? range->first : 0; f <= (range ? range->last : 0); ++f)
        files.push_back((dir / expand_frame_pattern(path, static_cast<int>(f))).lexically_normal());
    }
  }
  return files;
}

// A task whose status says "done" but one of whose files is gone (deleted
// after the run) is run again: resume used to exit 0 with the frame missing.
bool outputs_missing(const Task& t, const std::optional<LoadedGraph>& graph) {
  if (!graph) return false;
  try {
    for (const fs::path& f : expected_outputs(t, *graph))
      if (!fs::exists(f)) {
        std::cerr << "task " << t.id << " (" << t.name << ") is done but " << f.string() << " is missing: running it again\n";
        return true;
      }
  } catch (const std::exception&) {
    // Its outputs cannot be told from the graph: its status stands.
  }
  return false;
}

}  // namespace

// On Slurm as new arrays of only those ids, locally in the foreground.
int jobs_resume(JobManifest& m, int jobs) {
  std::vector<int> ids;
  std::optional<LoadedGraph> graph;
  int unused = 0;
  for (const Task& t : m.tasks) {
    const TaskStatus s = read_status(m.dir, t.id);
    const TaskState state = s.state;
    if (state == TaskState::running && still_running(m, s, t.id)) {
      std::cerr << "error: task " << t.id << " (" << t.name << ") is running: wait for it or `loom jobs cancel`\n";
      return kInvalid;
    }
    if (state == TaskState::done && !graph && fs::exists(m.dir / "graph.json"))
      graph = load_for_run((m.dir / "graph.json").string(), {}, &unused);
    if (state != TaskState::done || outputs_missing(t, graph)) ids.push_back(t.id);
  }
  if (ids.empty()) {
    std::cerr << "every task of " << m.dir.string() << " is done\n";
    return kOk;
  }
  std::cerr << "resuming " << ids.size() << " of " << m.tasks.size() << " tasks\n";
  if (jobs > 0) m.jobs = jobs;
  return m.to == "slurm" ? submit_slurm(m, ids) : dispatch_local(m, ids);
}

namespace {

int cancel_slurm(const JobManifest& m) {
  std::ifstream in(m.dir / "slurm" / "jobs");
  std::vector<std::string> argv = {"scancel"};
  for (std::string id; std::getline(in, id);)
    if (!id.empty()) argv.push_back(id);
  if (argv.size() == 1) {
    std::cerr << "nothing submitted from " << m.dir.string() << "\n";
    return kOk;
  }
  int exit = 0;
  capture_output(argv, &exit);
  std::cerr << "scancel " << argv.size() - 1 << " Slurm job" << (argv.size() == 2 ? "" : "s") << ": exit " << exit << "\n";
  return exit == 0 ? 0 : 3;
}

// SIGTERM to each task the status files say runs here, when its process is
// still the task's (a dispatcher killed by SIGKILL leaves them running).
int cancel_orphaned_tasks(const JobManifest& m) {
  int signalled = 0;
  for (const Task& t : m.tasks) {
    const TaskStatus s = read_status(m.dir, t.id);
    if (s.state != TaskState::running || s.host != host_name() || !task_process_alive(m.dir, s, t.id)) continue;
    const pid_t pid = static_cast<pid_t>(s.pid);
    ::kill(::getpgid(pid) == pid ? -pid : pid, SIGTERM);  // its group: the task and its `loom run`
    std::cerr << "sent SIGTERM to task " << t.id << " (" << t.name << ", pid " << pid << "), whose dispatcher is gone\n";
    ++signalled;
  }
  if (signalled == 0) std::cerr << "nothing of " << m.dir.string() << " is running on this machine\n";
  return kOk;
}

}  // namespace

int jobs_cancel(const JobManifest& m) {
  if (m.to == "slurm") return cancel_slurm(m);
  std::ifstream in(m.dir / "local.pid");
  long pid = 0;
  unsigned long long start = 0;
  if (in >> pid) in >> start;
  if (pid > 0 && same_process(pid, start, {})) {
    ::kill(static_cast<pid_t>(pid), SIGTERM);  // it passes SIGTERM on to every running task
    std::cerr << "sent SIGTERM to the local dispatcher (pid " << pid << ")\n";
    return kOk;
  }
  if (pid > 0 && process_start_time(pid) != 0)
    std::cerr << "local.pid names pid " << pid << ", which is no longer this job's dispatcher: not signalled\n";
  return cancel_orphaned_tasks(m);
}
}  // namespace loom::runner
