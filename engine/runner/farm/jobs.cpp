#include "farm/jobs.hpp"

#include <signal.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>

#include "farm/child_process.hpp"
#include "farm/dispatch.hpp"

namespace loom::runner {
namespace fs = std::filesystem;

int jobs_status(const JobManifest& m) {
  std::map<std::string, int> counts;
  for (const Task& t : m.tasks) {
    const TaskStatus s = read_status(m.dir, t.id);
    ++counts[s.state];
    std::printf("%4d  %-9s %-28s attempts %d  %7.2f s  %s%s\n", t.id, s.state.c_str(), t.name.c_str(), s.attempts,
                s.seconds, s.host.c_str(), s.message.empty() ? "" : ("  " + s.message).c_str());
  }
  std::printf("%zu tasks: %d done, %d failed, %d cancelled, %d running, %d pending (%s)\n", m.tasks.size(),
              counts["done"], counts["failed"], counts["cancelled"], counts["running"], counts["pending"],
              m.to.c_str());
  return counts["done"] == static_cast<int>(m.tasks.size()) ? 0 : 1;
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

// On Slurm as new arrays of only those ids, locally in the foreground.
int jobs_resume(JobManifest& m, int jobs) {
  std::vector<int> ids;
  for (const Task& t : m.tasks) {
    const TaskStatus s = read_status(m.dir, t.id);
    const std::string& state = s.state;
    if (state == "running" && still_running(m, s, t.id)) {
      std::cerr << "error: task " << t.id << " (" << t.name << ") is running: wait for it or `loom jobs cancel`\n";
      return 2;
    }
    if (state != "done") ids.push_back(t.id);
  }
  if (ids.empty()) {
    std::cerr << "every task of " << m.dir.string() << " is done\n";
    return 0;
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
    return 0;
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
    if (s.state != "running" || s.host != host_name() || !task_process_alive(m.dir, s, t.id)) continue;
    const pid_t pid = static_cast<pid_t>(s.pid);
    ::kill(::getpgid(pid) == pid ? -pid : pid, SIGTERM);  // its group: the task and its `loom run`
    std::cerr << "sent SIGTERM to task " << t.id << " (" << t.name << ", pid " << pid << "), whose dispatcher is gone\n";
    ++signalled;
  }
  if (signalled == 0) std::cerr << "nothing of " << m.dir.string() << " is running on this machine\n";
  return 0;
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
    return 0;
  }
  if (pid > 0 && process_start_time(pid) != 0)
    std::cerr << "local.pid names pid " << pid << ", which is no longer this job's dispatcher: not signalled\n";
  return cancel_orphaned_tasks(m);
}
}  // namespace loom::runner
