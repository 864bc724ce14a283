// A sequence run again, through the real `loom` command: the 60-frame curtain
// (graphs/cloth-curtain.json: three cloth simulations, Render at every frame,
// a PNG sequence, the meshes and an MP4) run once with an empty cache, then
// again unchanged; then, on another empty cache, interrupted (Ctrl-C) once
// half its frames are written and run again. Per run: wall seconds, the
// frames Render computed and read from disk, the cloth steps run, and what
// the cache holds. LOOM_BENCH_LOOM=path/to/loom measures another build (the
// figures before the storage rule in docs/time.md came from main's build).
// --min-seconds S passes --cache-min-seconds S: on a loaded machine every
// frame is slower, and a floor raised by the same factor puts the frames on
// the same side of it as on a quiet machine.
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>

#include "bench_harness.hpp"
#include "loom/evaluator.hpp"

namespace {

namespace fs = std::filesystem;
using loom::json;

std::string runner() {
  const char* other = std::getenv("LOOM_BENCH_LOOM");
  return other && *other ? other : LOOM_RUNNER;
}

double megabytes_in(const fs::path& dir) {
  std::uintmax_t bytes = 0;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec)) bytes += it->file_size(ec);
  return static_cast<double>(bytes) / (1024 * 1024);
}

struct Run {
  double seconds = 0;
  json profile;
};

// `loom run` of the graph; with `interrupt_after`, Ctrl-C once that file exists.
Run run(const fs::path& graph, const fs::path& dir, double min_seconds, const std::string& interrupt_after = "") {
  const fs::path profile = dir / "profile.json";
  fs::remove(profile);
  std::string cmd = runner() + " run " + graph.string() + " -q --out " + (dir / "out").string() + " --cache " +
                    (dir / "cache").string() + " --cache-min-seconds " + std::to_string(min_seconds) +
                    " --profile " + profile.string() + " > /dev/null 2>&1";
  if (!interrupt_after.empty())
    cmd = cmd + " & pid=$!; until [ -e " + (dir / "out" / interrupt_after).string() +
          " ] || ! kill -0 $pid 2>/dev/null; do sleep 0.05; done; kill -INT $pid; wait $pid";
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(cmd.c_str());
  Run r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status != 0 && interrupt_after.empty()) {
    std::cerr << "command failed: " << cmd << "\n";
    std::exit(1);
  }
  if (fs::exists(profile)) {
    std::ifstream in(profile);
    r.profile = json::parse(in);
  }
  return r;
}

int node_count(const json& profile, const std::string& node, const char* field) {
  return profile.is_null() ? -1 : profile["nodes"][node].value(field, 0);
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_engine_sequence_rerun",
                       "The 60-frame curtain run twice, and interrupted then run again: seconds, Render frames "
                       "computed and read from disk, cloth steps, cache size.");
  bool quick = false;
  double min_seconds = 0.05;
  cli.quick(quick, "the first 20 frames")
      .option("--min-seconds", min_seconds, "the runs' --cache-min-seconds (default 0.05, loom's own)");
  cli.parse(argc, argv);
  const fs::path graph = loom::bench::source_dir() / "graphs" / "cloth-curtain.json";
  const fs::path work = fs::temp_directory_path() / ("loom-bench-rerun-" + std::to_string(::getpid()));
  fs::remove_all(work);
  fs::path subject = graph;
  if (quick) {  // the same graph, 20 frames
    json g;
    std::ifstream(graph) >> g;
    g["time"]["end"] = 20;
    fs::create_directories(work);
    subject = work / "curtain-20.json";
    std::ofstream(subject) << g.dump(1);
  }
  std::cout << "runner " << runner() << ", load average " << loom::bench::load_average() << "\n";

  loom::bench::Csv csv("engine_sequence_rerun", {"step", "run", "seconds", "render_ran", "render_from_disk",
                                                 "cloth_steps", "cache_mb", "min_seconds", "load_average"});
  auto row = [&](int step, const std::string& name, const Run& r, const fs::path& dir) {
    const int steps = node_count(r.profile, "step10", "runs") + node_count(r.profile, "step20", "runs") +
                      node_count(r.profile, "step81", "runs");
    csv.row({static_cast<long long>(step), name, r.seconds,
             static_cast<long long>(node_count(r.profile, "render", "runs")),
             static_cast<long long>(node_count(r.profile, "render", "disk_hits")), static_cast<long long>(steps),
             megabytes_in(dir / "cache"), min_seconds, loom::bench::load_average()});
  };
  const fs::path a = work / "rerun", b = work / "interrupted";
  row(1, "first", run(subject, a, min_seconds), a);
  row(2, "rerun", run(subject, a, min_seconds), a);
  row(3, "interrupted", run(subject, b, min_seconds, quick ? "frames/curtains_0010.png" : "frames/curtains_0030.png"),
      b);
  row(4, "after_interrupt", run(subject, b, min_seconds), b);
  csv.save();
  loom::bench::plot(csv, {"step", "seconds", "", "Curtain: first run, rerun, interrupted, run again", false, false, ""});
  fs::remove_all(work);
  return 0;
}
