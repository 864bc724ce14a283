// A farm job as plain files (docs/farm.md): JOBDIR/manifest.json lists the
// tasks, each a `loom run` command line; JOBDIR/graph.json is the graph with
// every --set baked in; JOBDIR/slurm/ holds the scripts given to sbatch;
// JOBDIR/logs/task-NNNN.log each task's output; JOBDIR/status/NNNN.json how
// each task ended (written by `loom jobs task`, atomically).
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

struct TaskStatus {
  std::string state = "pending";  // pending, running, done, failed, cancelled
  int exit = -1;
  int attempts = 0;
  double seconds = 0;
  std::string host, message;
  long pid = 0;                   // of `loom jobs task` on `host`
  std::string loom;               // the executable that ran it (each node's own)
  std::vector<TaskTry> tries;     // the tries that ended before this one
};

// This machine's name, as the status files record it.
std::string host_name();

std::filesystem::path task_log(const std::filesystem::path& job, int id);
std::filesystem::path task_status_path(const std::filesystem::path& job, int id);

void save_manifest(const JobManifest& m);
// Throws Error naming the file when the folder is not a job folder.
JobManifest load_manifest(const std::filesystem::path& job);

TaskStatus read_status(const std::filesystem::path& job, int id);
void write_status(const std::filesystem::path& job, int id, const TaskStatus& s);

}  // namespace loom::runner
