#include "farm/farm_commands.hpp"

#include <iostream>

#include "cli/command_names.hpp"
#include "cli/exit_codes.hpp"
#include "farm/dispatch.hpp"
#include "farm/jobs.hpp"
#include "farm/submit.hpp"

namespace loom::runner {

namespace {

class Commands final : public FarmCommands {
 public:
  explicit Commands(CLI::App& app);
  bool chosen() const override { return *submit_ || *jobs_; }
  int run() override;

 private:
  CLI::App* submit_;
  CLI::App* jobs_;
  SubmitRequest request_;
  std::string action_, job_dir_;
  int task_ = -1, jobs_count_ = 0;
};

Commands::Commands(CLI::App& app) {
  submit_ = app.add_subcommand("submit", "Run a graph's frames or sweep points as tasks: on Slurm, or locally.");
  auto& r = request_;
  submit_->add_option("graph", r.run.graph_path, "graph file (JSON)")->required();
  submit_->add_option("--to", r.to, "slurm or local (default: slurm when sbatch is on PATH)")
      ->check(CLI::IsMember({"slurm", "local"}));
  submit_->add_option("--out", r.run.out_dir, "output folder, shared by every task")->capture_default_str();
  submit_->add_option("--job-dir", r.job_dir, "the job folder (default: OUT/.loom-job)");
  submit_->add_option("--frames", r.run.frames, "frames, A-B or A (default: the graph's \"time\" range)");
  submit_->add_option("--chunk", r.chunk, "frames (or sweep points) per task (default: 10 frames, 1 point)")
      ->check(whole_number_at_least(1));
  submit_->add_option("--retries", r.retries, "re-runs of a task that exits 1 or is killed by a signal")
      ->capture_default_str()
      ->check(whole_number_at_least(0));
  submit_->add_option("-j,--jobs", r.jobs, "local: tasks at once (default: the cores)")
      ->check(whole_number_at_least(1));
  submit_->add_option("--slurm-arg", r.slurm_args, "passed to sbatch, e.g. --slurm-arg=--partition=gpu (repeatable)")
      ->allow_extra_args(false);
  submit_
      ->add_option("--sim-chunk", r.sim_chunk,
                   "simulations as chained tasks of this many frames, each continuing from the last stored state")
      ->check(whole_number_at_least(1));
  submit_->add_option("--loom", r.node_loom,
                      "Slurm: the loom each node runs, a name on its PATH or a path (default: loom on the "
                      "node's PATH, else this one's path)");
  submit_->add_flag("--dry-run", r.dry_run, "write the job folder, submit nothing");
  submit_->add_option("--set", r.run.sets, "override an input: ID.INPUT=JSON (repeatable; baked into the job)");
  submit_->add_option("--target", r.run.targets, "evaluate ID or ID.OUTPUT instead of the sinks (repeatable)");
  submit_->add_option("--threads", r.run.threads, "worker threads per task (0: all cores)")
      ->check(whole_number_at_least(0));
  submit_->add_option("--cache", r.cache_dir, "the cache shared by the tasks (default: OUT/.loom-cache)");
  submit_->add_option("--cache-limit", r.cache_limit_mb, "cache size limit in MB")
      ->capture_default_str()
      ->check(number_above(0));
  submit_->add_option("--cache-min-seconds", r.cache_min_seconds, "store only results slower than this")
      ->capture_default_str()
      ->check(number_at_least(0));
  submit_->add_flag("--no-cache", r.no_cache, "tasks share no cache (simulations then re-simulate per chunk)");
  submit_->add_flag("--allow-outside-out", r.run.allow_outside, "as loom run");
  add_sweep_options(submit_, r.sweep);

  jobs_ = app.add_subcommand("jobs", "Status, resume or cancel of a job folder written by loom submit.");
  jobs_->add_option("action", action_, "status, resume, cancel (task: run one task, as Slurm does)")
      ->required()->check(CLI::IsMember({"status", "resume", "cancel", "task"}));
  jobs_->add_option("jobdir", job_dir_, "the job folder (OUT/.loom-job)")->required();
  jobs_->add_option("task", task_, "with `task`: the task id");
  jobs_->add_option("-j,--jobs", jobs_count_, "local resume: tasks at once")->check(whole_number_at_least(1));
}

int Commands::run() {
  if (*submit_) return submit(request_);
  JobManifest m;
  try {
    m = load_manifest(job_dir_);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kInvalid;
  }
  // A job folder that cannot be written (a read-only mount, a full disk) is
  // an error naming the file, never an abort.
  try {
    if (action_ == "status") return jobs_status(m);
    if (action_ == "resume") return jobs_resume(m, jobs_count_);
    if (action_ == "cancel") return jobs_cancel(m);
    return run_task(m, task_);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kNodeFailed;
  }
}


}  // namespace

std::unique_ptr<FarmCommands> add_farm_commands(CLI::App& app) { return std::make_unique<Commands>(app); }

}  // namespace loom::runner
