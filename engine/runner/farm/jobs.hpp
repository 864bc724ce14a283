// `loom jobs status|resume|cancel JOBDIR`: what a job folder's tasks did, the
// ones not done again, and cancelling (scancel, or SIGTERM to the local
// dispatcher). See docs/farm.md.
#pragma once

#include "farm/job_folder.hpp"

namespace loom::runner {

// Whether task `id`, whose status says "running", still runs: false when its
// process is gone (a node died, a SIGKILL), i.e. its pid on this machine has
// exited or now names another process, or on Slurm none of the job's Slurm
// jobs is queued or running.
bool still_running(const JobManifest& m, const TaskStatus& s, int id);
// Whether one of the Slurm jobs in JOBDIR/slurm/jobs is queued or running.
bool slurm_jobs_queued(const JobManifest& m);

// Prints every task and a summary; 0 when every task is done, else 1.
int jobs_status(const JobManifest& m);
// Runs every task not done again, with the job's dispatcher (`jobs` > 0:
// the local pool's size).
int jobs_resume(JobManifest& m, int jobs);
// Slurm: scancel of the recorded jobs. Locally: SIGTERM to the dispatcher
// (which passes it on), or, when the dispatcher is gone, to each task still
// running on this machine; a recorded pid is signalled only while it names
// the process that recorded it.
int jobs_cancel(const JobManifest& m);

}  // namespace loom::runner
