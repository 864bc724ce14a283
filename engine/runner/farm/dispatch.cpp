#include "farm/dispatch.hpp"

#include <dlfcn.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <cstring>
#include <map>
#include <optional>

#include "cli/exit_codes.hpp"
#include "cli/image_info.hpp"
#include "cli/run_settings.hpp"
#include "cli/signals.hpp"
#include "farm/child_process.hpp"
#include "farm/jobs.hpp"
#include "loom/atomic_file.hpp"
#include "loom/error.hpp"
#include "loom/graph.hpp"

namespace loom::runner {
namespace fs = std::filesystem;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The ids of `ids` in `stage`.
std::vector<int> in_stage(const JobManifest& m, const std::vector<int>& ids, Stage stage) {
  std::vector<int> out;
  for (int id : ids)
    if (m.tasks.at(static_cast<std::size_t>(id)).stage == stage) out.push_back(id);
  return out;
}

// `ids` (of one stage) by wave, in order: a wave runs after the one before it.
std::vector<std::vector<int>> waves(const JobManifest& m, const std::vector<int>& ids) {
  std::map<int, std::vector<int>> by_wave;
  for (int id : ids) by_wave[m.tasks.at(static_cast<std::size_t>(id)).wave].push_back(id);
  std::vector<std::vector<int>> out;
  for (auto& [wave, in_wave] : by_wave) out.push_back(std::move(in_wave));
  return out;
}

// Loads what each task of the job would load again — the plugins its graph
// uses and, with the io plugin, its image library (OpenImageIO: about 260
// shared libraries) — so that tasks forked from here find them mapped. Best
// effort and quiet: a task that cannot load them says so in its own log.
// Only then are the tasks' `loom run`s forks too (start_loom).
std::optional<LoadedGraph> warm_up(const JobManifest& m) {
  LoadedGraph g;
  try {
    g.graph = load_graph_file(m.dir / "graph.json");
    g.loader->load_for(node_types_used(g.graph));
  } catch (const std::exception&) {
    return std::nullopt;
  }
  const auto loaded = g.loader->loaded_names();
  const auto has = [&](const char* name) { return std::find(loaded.begin(), loaded.end(), name) != loaded.end(); };
  // Python nodes: the interpreter, started while loading, is not forked (its
  // own threads and NumPy's BLAS pool would not follow): such tasks start anew.
  if (has("python")) return std::nullopt;
  if (has("io"))
    ::dlopen(image_files_library().c_str(), RTLD_NOW | RTLD_LOCAL);  // never closed: the tasks use it
  fork_loom_runs(true);
  return g;
}

// A task's process: a fork of this dispatcher running `loom jobs task` in
// place when the job's `loom` is this very executable (what warm_up loaded
// is then mapped already), else `loom jobs task` started anew.
pid_t start_task(const JobManifest& m, int id, bool warm) {
  if (!warm || m.loom != own_executable())
    return spawn_process({m.loom, "jobs", "task", m.dir.string(), std::to_string(id)}, -1, true);
  return fork_call(
      [&] {
        try {
          return run_task(m, id);
        } catch (const std::exception& e) {  // as `loom jobs task` ends
          std::cerr << "error: " << e.what() << "\n";
          return static_cast<int>(kNodeFailed);
        }
      },
      true);
}

// Runs one stage's tasks with up to m.jobs at once; false if one failed.
bool run_stage(const JobManifest& m, const std::vector<int>& ids, bool warm) {
  std::map<pid_t, int> running;
  std::size_t next = 0;
  bool ok = true, forwarded = false;
  while (next < ids.size() || !running.empty()) {
    while (next < ids.size() && static_cast<int>(running.size()) < m.jobs && !cancel_flag()) {
      const int id = ids[next++];
      const pid_t pid = start_task(m, id, warm);
      if (pid < 0) {
        std::cerr << "error: cannot start " << m.loom << " for task " << id << ": " << std::strerror(errno) << "\n";
        ok = false;
        next = ids.size();
        continue;
      }
      running[pid] = id;
    }
    if (cancel_flag() && !forwarded) {  // as scancel: every process of every running task
      for (const auto& [pid, id] : running) ::kill(-pid, SIGTERM);
      forwarded = true;
      next = ids.size();
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    auto it = running.find(pid);
    if (it == running.end()) continue;
    const int id = it->second;
    running.erase(it);
    const TaskStatus s = read_status(m.dir, id);
    ok = ok && s.state == TaskState::done;
    std::fprintf(stderr, "task %d (%s): %s after %d attempt%s, %.2f s\n", id, m.tasks[id].name.c_str(),
                 task_state_text(s.state), s.attempts, s.attempts == 1 ? "" : "s", s.seconds);
  }
  return ok && !cancel_flag();
}

// Runs a stage's waves in order; a wave runs only if the one before succeeded.
bool run_waves(const JobManifest& m, const std::vector<int>& ids, bool warm) {
  bool ok = true;
  for (const auto& wave : waves(m, ids)) {
    if (cancel_flag()) return false;
    if (!ok) {
      std::cerr << "error: a simulation segment failed: " << wave.size() << " later segment"
                << (wave.size() == 1 ? "" : "s") << " did not run\n";
      return false;
    }
    ok = run_stage(m, wave, warm);
  }
  return ok;
}

// One job array per stage, and per wave within a stage, in the order they run.
std::vector<std::pair<Stage, std::vector<int>>> slurm_arrays(const JobManifest& m, const std::vector<int>& ids) {
  std::vector<std::pair<Stage, std::vector<int>>> out;
  for (Stage stage : {kSimulate, kWork, kAssemble})
    for (auto& wave : waves(m, in_stage(m, ids, stage))) out.emplace_back(stage, std::move(wave));
  return out;
}

std::string array_list(const std::vector<int>& ids) {
  std::string list;
  for (int id : ids) list += (list.empty() ? "" : ",") + std::to_string(id);
  return list;
}

}  // namespace

int dispatch_local(const JobManifest& m, const std::vector<int>& asked) {
  std::optional<JobLock> lock;  // one dispatcher per job at a time
  try {
    lock.emplace(m.dir);
    // With the start time, so that `jobs cancel` never signals a process that reused the pid.
    write_file_atomic(m.dir / "local.pid",
                      std::to_string(::getpid()) + " " + std::to_string(process_start_time(::getpid())) + "\n");
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kInvalid;
  }
  // What another dispatcher finished after this process started (between
  // its reading the statuses and taking the lock) is not run again.
  std::vector<int> ids;
  for (int id : asked) {
    std::error_code ec;
    const auto written = fs::last_write_time(task_status_path(m.dir, id), ec);
    if (ec || written < process_started() || read_status(m.dir, id).state != TaskState::done) ids.push_back(id);
  }
  const auto warm = ids.empty() ? std::nullopt : warm_up(m);
  stop_on_signals(Grace::none);
  bool ok = true, previous_ok = true;
  for (Stage stage : {kSimulate, kWork, kAssemble}) {
    const auto stage_ids = in_stage(m, ids, stage);
    if (stage_ids.empty() || cancel_flag()) continue;
    if (stage == kWork && !previous_ok) {
      std::cerr << "error: a simulation task failed: its " << stage_ids.size() << " render tasks did not run\n";
      ok = false;
      continue;
    }
    previous_ok = run_waves(m, stage_ids, warm.has_value());
    ok = ok && previous_ok;
  }
  std::error_code ec;
  fs::remove(m.dir / "local.pid", ec);
  if (cancel_flag()) {
    std::cerr << "interrupted: `loom jobs resume " << m.dir.string() << "` runs what is missing\n";
    return kInterrupted;
  }
  return ok ? 0 : 1;
}

int submit_slurm(const JobManifest& m, const std::vector<int>& ids) {
  std::optional<JobLock> lock;  // two resumes at once would submit every task twice
  try {
    lock.emplace(m.dir);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kInvalid;
  }
  if (slurm_jobs_queued(m)) {
    std::cerr << "error: Slurm jobs of " << m.dir.string() << " are still queued or running (squeue): wait for "
              << "them, or `loom jobs cancel " << m.dir.string() << "`\n";
    return kInvalid;
  }
  std::string previous;
  for (const auto& [stage, stage_ids] : slurm_arrays(m, ids)) {
    std::vector<std::string> argv = {"sbatch", "--parsable", "--array=" + array_list(stage_ids),
                                     "--job-name=loom-stage" + std::to_string(stage),
                                     "--output=" + (m.dir / "logs" / "slurm-%A_%a.out").string()};
    if (!previous.empty()) {
      argv.push_back(std::string("--dependency=") + (stage == kAssemble ? "afterany:" : "afterok:") + previous);
      argv.push_back("--kill-on-invalid-dep=yes");
    }
    // A task whose node fails is run again on another (docs/farm.md, "Lost
    // nodes"), unless --slurm-arg=--no-requeue, which comes after; the folder
    // loom submit ran in need not exist on the nodes.
    argv.insert(argv.end(), {"--requeue", "--chdir=" + m.dir.string()});
    argv.insert(argv.end(), m.slurm_args.begin(), m.slurm_args.end());
    argv.push_back((m.dir / "slurm" / ("stage" + std::to_string(stage) + ".sbatch")).string());
    int exit = 0;
    std::string out = capture_output(argv, &exit);
    const std::string job = out.substr(0, out.find_first_of(";\n"));
    if (exit != 0 || job.empty()) {
      std::cerr << "error: sbatch failed (exit " << exit << ") for stage " << stage << " of " << m.dir.string() << "\n";
      return kLaunchFailed;
    }
    append_line(m.dir / "slurm" / "jobs", job);
    std::fprintf(stderr, "submitted %zu task%s as Slurm job %s\n", stage_ids.size(), stage_ids.size() == 1 ? "" : "s",
                 job.c_str());
    previous = job;
  }
  return kOk;
}

namespace {

// The assemble task runs only when every other task is done.
std::string missing_tasks(const JobManifest& m) {
  std::string missing;
  for (const Task& t : m.tasks)
    if (t.stage != kAssemble && read_status(m.dir, t.id).state != TaskState::done)
      missing += (missing.empty() ? "" : ", ") + std::to_string(t.id) + " (" + t.name + ")";
  return missing;
}

std::string try_end(int exit, bool signalled) {
  if (exit == 0) return "done";
  return signalled ? "signal " + std::to_string(exit - 128) : "exit " + std::to_string(exit);
}

// The tries before this run of the task, from its status. One that the status
// says is running ended without a word: its node died or its process was
// killed (SIGKILL), and Slurm requeued the task (SLURM_RESTART_COUNT) or
// `loom jobs resume` runs it again.
std::vector<TaskTry> earlier_tries(const JobManifest& m, int id) {
  TaskStatus before = read_status(m.dir, id);
  if (before.state == TaskState::running) {
    const char* restarts = std::getenv("SLURM_RESTART_COUNT");
    const bool requeued = restarts && std::atoi(restarts) > 0;
    before.tries.push_back(
        {before.host, requeued ? "lost (its node failed; requeued by Slurm)" : "lost (its process vanished)", 0});
  }
  return before.tries;
}

}  // namespace

namespace {

// One attempt of the task's `loom run`, its output appended to the log.
int run_attempt(const JobManifest& m, int id, const std::vector<std::string>& argv, bool* signalled) {
  const int log = open_task_log(m.dir, id);
  const pid_t pid = start_loom(argv, log, false);
  const int error = errno;
  ::close(log);
  if (pid < 0) {
    append_task_log(m.dir, id, "error: cannot start " + argv[0] + ": " + std::strerror(error));
    return kLaunchFailed;
  }
  int exit = -1;
  while ((exit = wait_process(pid, signalled)) == -1 && errno == EINTR) {
  }
  return exit;
}

}  // namespace

int run_task(const JobManifest& m, int id) {
  if (id < 0 || id >= static_cast<int>(m.tasks.size())) {
    std::cerr << "error: " << m.dir.string() << " has no task " << id << " (its tasks are 0 to "
              << static_cast<long>(m.tasks.size()) - 1 << ")\n";
    return kInvalid;
  }
  stop_on_signals(Grace::none);
  const Task& task = m.tasks[static_cast<std::size_t>(id)];
  const auto start = std::chrono::steady_clock::now();
  check_job_subfolders(m.dir);  // logs/ or status/ deleted by hand: made again
  TaskStatus s;
  s.tries = earlier_tries(m, id);
  s.state = TaskState::running;
  s.host = host_name();
  s.pid = ::getpid();
  s.pid_start = process_start_time(s.pid);
  // This node's own loom runs the task, not the submitting machine's path:
  // nodes may have Loom installed at different prefixes.
  s.loom = own_executable();
  if (s.loom.empty()) s.loom = m.loom;
  s.attempts = static_cast<int>(s.tries.size()) + 1;
  write_status(m.dir, id, s);
  const fs::path log = task_log(m.dir, id);
  try {
    if (task.stage == kAssemble) {
      if (std::string missing = missing_tasks(m); !missing.empty()) {
        s.state = TaskState::failed;
        s.exit = 1;
        s.message = "not every task is done: " + missing + " (loom jobs resume runs them)";
        s.tries.push_back({s.host, "exit 1", 0});
        append_task_log(m.dir, id, "error: " + s.message);
        write_status(m.dir, id, s);
        return kNodeFailed;
      }
    }
    std::vector<std::string> argv = {s.loom};
    argv.insert(argv.end(), task.args.begin(), task.args.end());
    for (int attempt = 1;; ++attempt) {
      append_task_log(m.dir, id, "== " + task.name + ": attempt " + std::to_string(s.attempts) + " on " + s.host +
                                     " (" + s.loom + ")");
      const auto tried = std::chrono::steady_clock::now();
      bool signalled = false;
      s.exit = run_attempt(m, id, argv, &signalled);
      s.tries.push_back({s.host, try_end(s.exit, signalled), seconds_since(tried)});
      const bool retry = s.exit == 1 || (signalled && !cancel_flag());
      if (s.exit == 0 || !retry || attempt > m.retries || cancel_flag()) break;
      append_task_log(m.dir, id, "== exit " + std::to_string(s.exit) + ": retrying");
      s.attempts = static_cast<int>(s.tries.size()) + 1;
      write_status(m.dir, id, s);  // should this node be lost now, the next run knows the tries so far
    }
    s.message = s.exit == 0 ? "" : "exit " + std::to_string(s.exit) + ", see " + log.string();
  } catch (const Error& e) {  // the log cannot be written: say why in the status
    s.exit = 2;
    s.message = e.what();
    std::cerr << "error: task " << id << " (" << task.name << "): " << e.what() << "\n";
  }
  s.attempts = static_cast<int>(s.tries.size());
  s.seconds = seconds_since(start);
  s.state = s.exit == 0                               ? TaskState::done
            : s.exit == kInterrupted || cancel_flag() ? TaskState::cancelled
                                                      : TaskState::failed;
  if (cancel_flag() && s.exit != 130) s.exit = 130;
  write_status(m.dir, id, s);
  return s.exit;
}

}  // namespace loom::runner
