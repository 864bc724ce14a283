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
  std::map<std::string, int> counts;
  for (const Task& t : m.tasks) {
    const TaskStatus s = read_status(m.dir, t.id);
    ++counts[s.state];
    std::printf("%4d  %-9s %-28s attempts %d  %7.2f s  %s%s\n", t.id, s.state.c_str(), t.name.c_str(), s.attempts,
                s.seconds, s.host.c_str(), s.message.empty() ? "" : ("  " + s.message).c_str());
    print_tries(s);
  }
  std::printf("%zu tasks: %d done, %d failed, %d cancelled, %d running, %d pending (%s)\n", m.tasks.size(),
              counts["done"], counts["failed"], counts["cancelled"], counts["running"], counts["pending"],
              m.to.c_str());
  return counts["done"] == static_cast<int>(m.tasks.size()) ? 0 : 1;
}

bool still_running(const JobManifest& m, const TaskStatus& s) {
  if (s.host == host_name()) return s.pid > 0 && fs::exists("/proc/" + std::to_string(s.pid));
  if (m.to != "slurm") return true;  // another machine's process: cannot tell
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

// On Slurm as new arrays of only those ids, locally in the foreground.
int jobs_resume(JobManifest& m, int jobs) {
  std::vector<int> ids;
  for (const Task& t : m.tasks) {
    const TaskStatus s = read_status(m.dir, t.id);
    const std::string& state = s.state;
    if (state == "running" && still_running(m, s)) {
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

int jobs_cancel(const JobManifest& m) {
  if (m.to == "slurm") {
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
  std::ifstream in(m.dir / "local.pid");
  long pid = 0;
  if (!(in >> pid) || pid <= 0 || !fs::exists("/proc/" + std::to_string(pid))) {
    std::cerr << "no local dispatcher is running for " << m.dir.string() << "\n";
    return 0;
  }
  ::kill(static_cast<pid_t>(pid), SIGTERM);  // it passes SIGTERM on to every running task
  std::cerr << "sent SIGTERM to the local dispatcher (pid " << pid << ")\n";
  return 0;
}
}  // namespace loom::runner
