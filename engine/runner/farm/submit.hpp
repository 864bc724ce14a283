// `loom submit`: a graph's frames, sweep points and simulations as the tasks
// of a job folder (job_folder.hpp), then run by Slurm or by the local
// dispatcher (dispatch.hpp). See docs/farm.md.
#pragma once

#include <string>
#include <vector>

#include "cli/run_settings.hpp"
#include "sweep/sweep.hpp"

namespace loom::runner {

struct SubmitRequest {
  RunSettings run;
  SweepRequest sweep;
  std::string to, job_dir, cache_dir;  // empty: slurm when sbatch is on PATH; OUT/.loom-job; OUT/.loom-cache
  int chunk = 0, retries = 2, jobs = 0;  // 0: 10 frames or 1 point; -; the cores
  double cache_limit_mb = 10240, cache_min_seconds = 0.05;
  bool no_cache = false, dry_run = false;
  std::vector<std::string> slurm_args;
  // --sim-chunk: a simulation as chained tasks of this many frames (0: one task).
  int sim_chunk = 0;
  // --loom: what the Slurm tasks run on each node (empty: `loom` on the node's
  // PATH, else the submitting loom's path).
  std::string node_loom;
};

// Validates, writes the job folder and (unless dry_run) submits or runs it.
// Returns loom's exit codes (2: invalid graph or usage).
int submit(SubmitRequest& request);

}  // namespace loom::runner
