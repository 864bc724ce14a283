// Running a job folder's tasks: on this machine by a pool of processes (the
// local dispatcher), or on Slurm as one sbatch job array per stage, each stage
// depending on the previous one. Every task runs `loom jobs task JOBDIR ID`.
#pragma once

#include <vector>

#include "farm/job_folder.hpp"

namespace loom::runner {

// Runs the tasks `ids` stage by stage with up to m.jobs
// processes at once; a stage runs only if the one before it succeeded, except
// the assemble stage, which always runs (and reports what is missing).
// Ctrl-C or SIGTERM passes SIGTERM to every running task's process group.
// Returns 0, 1 (a task failed) or 130 (interrupted).
int dispatch_local(const JobManifest& m, const std::vector<int>& ids);

// Submits the tasks `ids` with sbatch: per stage a job array of those task
// ids, --dependency=afterok on the previous stage (afterany for the assemble
// stage), plus m.slurm_args. Appends the Slurm job ids to JOBDIR/slurm/jobs.
// Returns 0, or 3 when sbatch fails (its message printed).
int submit_slurm(const JobManifest& m, const std::vector<int>& ids);

// `loom jobs task JOBDIR ID`: runs one task's `loom run` with retries (exit 1
// or a signal: again, up to m.retries times; 2, 3 and 130: never), and writes
// its status. The assemble task first checks that every other task is done.
int run_task(const JobManifest& m, int id);

}  // namespace loom::runner
