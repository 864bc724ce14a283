// A farm job as plain files (docs/farm.md): JOBDIR/manifest.json lists the
// tasks, each a `loom run` command line; JOBDIR/graph.json is the graph with
// every --set baked in; JOBDIR/slurm/ holds the scripts given to sbatch;
// JOBDIR/logs/task-NNNN.log each task's output; JOBDIR/status/NNNN.json how
// each task ended (written by `loom jobs task`, atomically).
//
// A job folder may sit on a shared filesystem that others write to, and its
// files may be edited: a manifest is checked whole before anything runs, the
// folders Loom writes into are never followed through symbolic links, and a
// recorded pid is signalled only while it names the process that wrote it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "loom/value.hpp"

namespace loom::runner {

// Stages run in order: simulations, then frame chunks or sweep points, then
// the assemble task (sequence sinks, sweep tables, the cache trim).
enum Stage { kSimulate = 0, kWork = 1, kAssemble = 2 };

struct Task {
  int id = 0;
  std::string name;              // "frames 1-12", "simulate sim", "point 3", "assemble"
  Stage stage = kWork;
  std::vector<std::string> args;  // after the loom executable
  // Within a stage, wave w runs after wave w - 1 succeeded: the segments of a
  // simulation split by --sim-chunk (each continues from the state the one
  // before stored). 0 for every other task.
  int wave = 0;
};

struct JobManifest {
  std::filesystem::path dir;      // the job folder (absolute)
  std::string loom;               // the loom executable every task runs
  std::string to = "local";       // "local" or "slurm"
  int retries = 0;
  int jobs = 1;                   // local: processes at once
  std::vector<std::string> slurm_args;
  std::vector<Task> tasks;
  // What the Slurm scripts run on each node: empty: `loom` on the node's PATH,
  // else `loom` above; a name: found on the node's PATH; a path: that file.
  std::string node_loom;
};

// One run of a task that ended, kept so that `loom jobs status` can say on
// which node each try ran and why it was tried again.
struct TaskTry {
  std::string host;
  std::string end;  // "done", "exit 1", "signal 9", "lost" (ended without a word: its node died)
  double seconds = 0;
};

// Where a task stands, as its status file says it in words.
enum class TaskState { pending, running, done, failed, cancelled };
const char* task_state_text(TaskState state);
// nullopt for a word no status file holds.
std::optional<TaskState> task_state_from_text(const std::string& text);

struct TaskStatus {
  TaskState state = TaskState::pending;
  int exit = -1;
  int attempts = 0;
  double seconds = 0;
  std::string host, message;
  long pid = 0;                   // of `loom jobs task` on `host`
  std::string loom;               // the executable that ran it (each node's own)
  std::vector<TaskTry> tries;     // the tries that ended before this one
  // That process's start time (/proc/PID/stat), so that a pid reused by an
  // unrelated process is not taken for the task (0: not recorded).
  unsigned long long pid_start = 0;
};

// This machine's name, as the status files record it.
std::string host_name();

std::filesystem::path task_log(const std::filesystem::path& job, int id);
std::filesystem::path task_status_path(const std::filesystem::path& job, int id);

void save_manifest(const JobManifest& m);
// Throws Error naming the file when the folder is not a job folder, and the
// task and key when the manifest is not one `loom submit` could have written
// (ids out of order, an unknown stage, "jobs" below 1, arguments that are not
// strings) or a folder Loom writes into is a symbolic link.
JobManifest load_manifest(const std::filesystem::path& job);

// The log of task `id`, opened to append (close it after use): never through
// a symbolic link (the log or JOB/logs), JOB/logs made again when missing.
// Throws Error naming the log and why it cannot be opened.
int open_task_log(const std::filesystem::path& job, int id);
// Appends a line to the task's log (as open_task_log).
void append_task_log(const std::filesystem::path& job, int id, const std::string& line);
// Appends a line to a file of the job (slurm/jobs), never through a link.
void append_line(const std::filesystem::path& file, const std::string& line);
// Makes JOB/logs, status, profiles and slurm when missing; throws Error when
// one of them is a symbolic link (it would send the job's files elsewhere).
void check_job_subfolders(const std::filesystem::path& job);

// When this process started (as file times are kept).
std::filesystem::file_time_type process_started();

// The start time of process `pid` in clock ticks after boot (field 22 of
// /proc/PID/stat), or 0 when no such process runs.
unsigned long long process_start_time(long pid);
// Whether `pid` on this machine is still the process that started at `start`
// (0: unknown; then whether its command line is `loom ... KEYWORDS...`).
bool same_process(long pid, unsigned long long start, const std::vector<std::string>& keywords);

// Held by the one process that runs a job's tasks (the local dispatcher, or
// a resume submitting to Slurm): an flock on JOB/lock. The tasks it starts
// inherit it, so a second dispatcher is refused while any of them runs, also
// after the first one was killed.
class JobLock {
 public:
  // Throws Error saying who holds the lock (its pid) when it is taken.
  explicit JobLock(const std::filesystem::path& job);
  ~JobLock();
  JobLock(const JobLock&) = delete;
  JobLock& operator=(const JobLock&) = delete;

 private:
  int fd_ = -1;
};

TaskStatus read_status(const std::filesystem::path& job, int id);
void write_status(const std::filesystem::path& job, int id, const TaskStatus& s);

}  // namespace loom::runner
