#include "farm/submit.hpp"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>

#include "farm/bundle.hpp"
#include "farm/dispatch.hpp"
#include "farm/job_folder.hpp"
#include "farm/jobs.hpp"
#include "loom/atomic_file.hpp"
#include "cli/run_settings.hpp"
#include "sweep/sweep.hpp"

namespace loom::runner {
namespace fs = std::filesystem;

namespace {

// The file `program` names on PATH, or "".
std::string which(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  for (std::size_t at = 0; at <= dirs.size();) {
    const std::size_t end = std::min(dirs.find(':', at), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(at, end - at)) / program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    at = end + 1;
  }
  return "";
}

std::string self_executable() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("loom") : p.string();
}

// What every task's `loom run` is given: the job's copy of the graph, the
// --set values (input paths made absolute); `worker`: never trims the cache.
std::vector<std::string> common_args(const SubmitRequest& r, const GraphView& view, const fs::path& job, bool worker) {
  std::vector<std::string> a = {"run", (job / "graph.json").string(), "--out", fs::absolute(r.run.out_dir).string()};
  for (const auto& s : r.run.sets) a.insert(a.end(), {"--set", task_assignment(view, s)});
  if (r.run.threads > 0) a.insert(a.end(), {"--threads", std::to_string(r.run.threads)});
  if (r.run.allow_outside) a.push_back("--allow-outside-out");
  if (r.no_cache) {
    a.push_back("--no-cache");
    return a;
  }
  a.insert(a.end(), {"--cache", fs::absolute(r.cache_dir).string(), "--cache-limit", json(r.cache_limit_mb).dump()});
  if (worker) a.push_back("--cache-no-trim");
  return a;
}

void add_profile(std::vector<std::string>& args, const fs::path& job, int id) {
  char name[32];
  std::snprintf(name, sizeof name, "%04d.json", id);
  args.insert(args.end(), {"--profile", (job / "profiles" / name).string()});
}

std::string min_seconds(double s) { return json(s).dump(); }

}  // namespace

namespace {

struct Planner {
  const SubmitRequest& r;
  const GraphView& view;
  fs::path job;
  std::vector<Task> tasks;

  void add(std::string name, Stage stage, std::vector<std::string> args) {
    const int id = static_cast<int>(tasks.size());
    add_profile(args, job, id);
    tasks.push_back({id, std::move(name), stage, std::move(args), 0});
  }

  std::vector<std::string> sweep_args(bool assemble) const {
    std::vector<std::string> a;
    for (const auto& s : r.sweep.axes) a.insert(a.end(), {"--sweep", s});
    if (r.sweep.zip) a.push_back("--zip");
    for (const auto& s : r.sweep.records) a.insert(a.end(), {"--record", s});
    if (assemble)
      for (const auto& s : r.sweep.plots) a.insert(a.end(), {"--plot", s});
    if (!r.run.frames.empty()) a.insert(a.end(), {"--frames", r.run.frames});
    for (const auto& t : r.run.targets) a.insert(a.end(), {"--target", t});
    a.insert(a.end(), {"--cache-min-seconds", min_seconds(r.cache_min_seconds)});
    return a;
  }

  // One task per --chunk points (default 1), then the tables.
  void plan_points(std::size_t count) {
    const std::size_t chunk = r.chunk > 0 ? static_cast<std::size_t>(r.chunk) : 1;
    for (std::size_t first = 0; first < count; first += chunk) {
      std::string list;
      for (std::size_t i = first; i < std::min(count, first + chunk); ++i)
        list += (list.empty() ? "" : ",") + std::to_string(i);
      auto a = common_args(r, view, job, true);
      auto s = sweep_args(false);
      a.insert(a.end(), s.begin(), s.end());
      a.insert(a.end(), {"--sweep-points", list});
      add("points " + list, kWork, a);
    }
    auto a = common_args(r, view, job, false);
    auto s = sweep_args(true);
    a.insert(a.end(), s.begin(), s.end());
    a.push_back("--sweep-collect");
    add("assemble sweep tables", kAssemble, a);
  }

  void plan_frames(FrameRange range);
  void plan_simulations(const std::vector<std::string>& simulations, FrameRange range);
};

// Each simulation from the start frame, every state into the shared cache: in
// one task, or (--sim-chunk K) in segments of K frames, segment w in wave w,
// each continuing from the state the one before stored (the engine steps on
// from the latest stored state), so a lost node or a Ctrl-C costs at most the
// segment it interrupted.
void Planner::plan_simulations(const std::vector<std::string>& simulations, FrameRange range) {
  const long size = r.sim_chunk > 0 ? r.sim_chunk : range.last - range.first + 1;
  for (const auto& id : simulations) {
    int wave = 0;
    for (long first = range.first; first <= range.last; first += size, ++wave) {
      const std::string frames =
          std::to_string(first) + "-" + std::to_string(std::min<long>(first + size - 1, range.last));
      auto a = common_args(r, view, job, true);
      a.insert(a.end(), {"--frames", frames, "--target", id, "--cache-min-seconds", "0"});
      add("simulate " + id + " " + frames, kSimulate, a);
      tasks.back().wave = wave;
    }
  }
}

// Simulations first (each from the start frame, every state into the shared
// cache), then contiguous chunks of --chunk frames (the last one clamped at
// the range's end), then the sequence sinks over the whole range.
void Planner::plan_frames(FrameRange range) {
  const RunStages stages = view.stages(r.run.targets);
  const std::vector<std::string>& simulations = stages.simulations;
  std::vector<std::string> chunk_targets = stages.per_frame, sequence = stages.sequences;
  const bool split = (r.sim_chunk > 0 && !simulations.empty()) ||
                     (r.chunk > 0 ? range.last - range.first + 1 > r.chunk : range.last - range.first + 1 > 10);
  if (!split) {  // one task runs everything
    chunk_targets = r.run.targets;
    sequence.clear();
  }
  const std::string whole = std::to_string(range.first) + "-" + std::to_string(range.last);
  if (split && !r.no_cache) plan_simulations(simulations, range);
  const int chunk = r.chunk > 0 ? r.chunk : 10;
  for (long first = range.first; first <= range.last; first += chunk) {
    const long last = std::min<long>(first + chunk - 1, range.last);
    auto a = common_args(r, view, job, true);
    const std::string frames = std::to_string(first) + "-" + std::to_string(last);
    a.insert(a.end(), {"--frames", frames});
    if (!stages.sequences.empty() || !r.run.targets.empty())
      for (const auto& t : chunk_targets) a.insert(a.end(), {"--target", t});
    // What the sequence sinks read is kept, however cheap, for the assemble task.
    a.insert(a.end(), {"--cache-min-seconds", sequence.empty() ? min_seconds(r.cache_min_seconds) : "0"});
    add("frames " + frames, kWork, a);
  }
  if (sequence.empty()) return;
  auto a = common_args(r, view, job, false);
  a.insert(a.end(), {"--frames", whole});
  for (const auto& id : sequence) a.insert(a.end(), {"--target", id});
  add("assemble " + whole, kAssemble, a);
}

}  // namespace

namespace {

// The script's lines that set $loom: the node's own loom (nodes may have it at
// different prefixes), found when the task starts on the node.
std::string node_loom_lines(const JobManifest& m) {
  if (!m.node_loom.empty())
    return "loom=$(command -v '" + m.node_loom + "') || { echo \"error: no " + m.node_loom +
           " on $(hostname) (PATH=$PATH)\" >&2; exit 3; }\n";
  return "# Each node's own: `loom` on the node's PATH, else the path that submitted.\n"
         "loom=$(command -v loom) || loom='" +
         m.loom + "'\n";
}

void write_slurm_scripts(const JobManifest& m) {
  for (int stage : {kSimulate, kWork, kAssemble}) {
    const std::string script = "#!/bin/sh\n"
                               "# Stage " +
                               std::to_string(stage) +
                               " of a loom job: one array element per task; the element's index\n"
                               "# is the task id in manifest.json. `loom submit` passes --array and --dependency.\n" +
                               node_loom_lines(m) + "exec \"$loom\" jobs task '" + m.dir.string() +
                               "' \"$SLURM_ARRAY_TASK_ID\"\n";
    const fs::path path = m.dir / "slurm" / ("stage" + std::to_string(stage) + ".sbatch");
    write_file_atomic(path, script);
    fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec, fs::perm_options::add);
  }
}

// A job folder from an earlier submit is replaced, unless one of its tasks
// runs. Any other folder that holds anything (a project folder, `.`) is
// refused before anything in it is touched: submit writes graph.json and
// clears logs/, status/, profiles/ and slurm/, which may be the user's own.
bool clear_job_folder(const fs::path& job) {
  std::error_code ec;
  const bool empty = !fs::exists(job, ec) || (fs::is_directory(job, ec) && fs::is_empty(job, ec));
  if (!empty) {
    std::optional<JobManifest> old;
    try {
      old = load_manifest(job);
    } catch (const std::exception& e) {
      std::cerr << "error: --job-dir " << job.string() << " is not a Loom job folder and not empty ("
                << (fs::exists(job / "manifest.json", ec) ? e.what() : "it has no manifest.json written by loom submit")
                << "): submit never overwrites a folder it did not make; give a new or empty folder\n";
      return false;
    }
    for (const Task& t : old->tasks)
      if (const TaskStatus s = read_status(job, t.id); s.state == TaskState::running && still_running(*old, s, t.id)) {
        std::cerr << "error: task " << t.id << " of the job in " << job.string()
                  << " is running: `loom jobs cancel` it first, or give another --job-dir\n";
        return false;
      }
  }
  for (const char* sub : {"logs", "status", "slurm", "profiles"}) fs::remove_all(job / sub, ec);
  return true;
}

}  // namespace

int submit(SubmitRequest& r) {
  int exit = 0;
  auto g = load_for_run(r.run.graph_path, r.run.sets, &exit);
  if (!g) return exit;
  const GraphView view(g->graph, *g->registry);
  if (r.sim_chunk > 0 && r.no_cache) {
    std::cerr << "error: --sim-chunk hands each segment's last state to the next through the shared cache: "
                 "not with --no-cache\n";
    return kInvalid;
  }
  if (r.cache_dir.empty()) r.cache_dir = (fs::path(r.run.out_dir) / ".loom-cache").string();
  const fs::path job = fs::absolute(r.job_dir.empty() ? fs::path(r.run.out_dir) / ".loom-job" : fs::path(r.job_dir));
  Planner plan{r, view, job, {}};
  std::optional<FrameRange> range;
  if (!r.run.frames.empty() && !(range = parse_frame_range(r.run.frames))) {
    std::cerr << "error: --frames: expected A-B or A (whole frame numbers, A <= B), got \"" << r.run.frames << "\"\n";
    return kInvalid;
  }
  if (!range && g->graph.time) range = FrameRange{g->graph.time->start, g->graph.time->end};
  if (range)  // a task per chunk of an endless range would exhaust memory before the first ran
    if (auto problem = frame_count_problem(*range, r.run.frames.empty() ? "the graph's time range" : "--frames")) {
      std::cerr << "error: " << *problem << "\n";
      return kInvalid;
    }
  if (r.sweep.active()) {
    const auto count = check_sweep(r.sweep, r.run, *g);
    if (!count) return kInvalid;
    plan.plan_points(*count);
  } else if (range) {
    plan.plan_frames(*range);
  } else {
    auto a = common_args(r, view, job, false);
    for (const auto& t : r.run.targets) a.insert(a.end(), {"--target", t});
    plan.add("run", kWork, a);
  }
  if (r.to.empty()) r.to = !which("sbatch").empty() ? "slurm" : "local";
  const int cores = static_cast<int>(std::max(1L, ::sysconf(_SC_NPROCESSORS_ONLN)));
  JobManifest m{job,          self_executable(), r.to,       r.retries, r.jobs > 0 ? r.jobs : cores,
                r.slurm_args, plan.tasks,        r.node_loom};
  try {
    if (!clear_job_folder(job)) return kInvalid;
    save_manifest(m);
    write_bundle(view, *g->registry, job);
    write_slurm_scripts(m);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kNodeFailed;
  }
  std::fprintf(stderr, "job folder: %s (%zu tasks, %s)\n", job.c_str(), m.tasks.size(), m.to.c_str());
  if (m.to == "slurm" && m.node_loom.empty()) {
    // The scripts prefer the nodes' own `loom`: say so when it is not this one.
    std::error_code ec;
    const std::string here = which("loom");
    if (!here.empty() && !fs::equivalent(here, m.loom, ec))
      std::fprintf(stderr, "note: tasks run `loom` on each node's PATH (here %s, not %s); --loom PATH picks one\n",
                   here.c_str(), m.loom.c_str());
  }
  if (r.dry_run) {  // what would run: each task, its stage and its command
    for (const Task& t : m.tasks) {
      std::string command = "loom";
      for (const auto& a : t.args) command += " " + a;
      std::fprintf(stdout, "task %d (stage %d) %s: %s\n", t.id, static_cast<int>(t.stage), t.name.c_str(), command.c_str());
    }
    return kOk;
  }
  std::vector<int> ids;
  for (const Task& t : m.tasks) ids.push_back(t.id);
  return m.to == "slurm" ? submit_slurm(m, ids) : dispatch_local(m, ids);
}

}  // namespace loom::runner
