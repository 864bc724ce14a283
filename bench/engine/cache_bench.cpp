// The persistent cache and time, measured through the real `loom` command:
//  1. read throughput of the disk cache against entry size (where the store
//     threshold should sit: reading must be much faster than recomputing);
//  2. first run against second run with the cache of a 2048² Poisson blend and
//     a ~100k-face ARAP (whole run and the node alone: its compute time against
//     its disk read time);
//  3. a 240-frame graph whose only time-dependent node is cheap: how often its
//     expensive static part runs;
//  4. the cost of the one copy per frame a simulation step makes of its state.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>

#include <unistd.h>

#include <Eigen/Core>

#include "bench_harness.hpp"
#include "loom/disk_cache.hpp"
#include "loom/evaluator.hpp"

namespace {

namespace fs = std::filesystem;
using loom::json;

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

// Runs `loom run`; returns wall seconds and the profile.
std::pair<double, json> run(const fs::path& graph, const std::string& args, const fs::path& dir) {
  const fs::path profile = dir / "profile.json";
  const std::string cmd = std::string(LOOM_RUNNER) + " run " + graph.string() + " -q --out " + (dir / "out").string() +
                          " --profile " + profile.string() + " " + args + " > /dev/null";
  auto start = std::chrono::steady_clock::now();
  if (std::system(cmd.c_str()) != 0) {
    std::cerr << "command failed: " << cmd << "\n";
    std::exit(1);
  }
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), read_json(profile)};
}

fs::path write_graph(const fs::path& dir, const std::string& name, const json& g) {
  fs::create_directories(dir);
  std::ofstream(dir / name) << g.dump(1);
  return dir / name;
}

json poisson_graph(int size) {
  const double s = size / 512.0;
  json polygon = json::array();
  for (auto [x, y] : std::vector<std::pair<double, double>>{{128, 8}, {158, 92}, {248, 96}, {176, 150}, {204, 240},
                                                           {128, 186}, {52, 240}, {80, 150}, {8, 96}, {98, 92}})
    polygon.push_back({x * s, y * s});
  return {{"loom", 1},
          {"nodes",
           {{"target", {{"type", "Checkerboard"}, {"inputs", {{"size", {size, size}}, {"cells", 8}}}}},
            {"source", {{"type", "Checkerboard"}, {"inputs", {{"size", {size / 2, size / 2}}, {"cells", 10},
                                                              {"color_a", {0.95, 0.6, 0.2}}}}}},
            {"blend", {{"type", "PoissonBlend"},
                       {"inputs", {{"source", {{"from", "source.image"}}}, {"target", {{"from", "target.image"}}},
                                   {"polygon", polygon}, {"offset", {size / 4, size / 8}}}}}}}}};
}

json arap_graph(int rings, int segments) {
  return {{"loom", 1},
          {"nodes",
           {{"dome", {{"type", "HemisphereMesh"}, {"inputs", {{"rings", rings}, {"segments", segments}, {"noise", 0.02}}}}},
            {"arap", {{"type", "ARAP"}, {"inputs", {{"mesh", {{"from", "dome.mesh"}}}, {"init", "tutte"}}}}}}}};
}

json time_graph() {
  return {{"loom", 1},
          {"time", {{"start", 1}, {"end", 240}, {"fps", 24}}},
          {"nodes",
           {{"target", {{"type", "Checkerboard"}, {"inputs", {{"size", {512, 512}}}}}},
            {"source", {{"type", "Checkerboard"}, {"inputs", {{"size", {256, 256}}, {"cells", 5}}}}},
            {"blend", {{"type", "PoissonBlend"},
                       {"inputs", {{"source", {{"from", "source.image"}}}, {"target", {{"from", "target.image"}}},
                                   {"polygon", {{10, 10}, {240, 20}, {200, 230}, {20, 200}}}, {"offset", {100, 100}}}}}},
            {"time", {{"type", "Time"}}},
            {"frame", {{"type", "Math"}, {"inputs", {{"a", {{"from", "time.seconds"}}}, {"b", 2}}}}},
            {"print", {{"type", "Print"}, {"inputs", {{"value", {{"from", "frame.result"}}}}}}},
            {"save", {{"type", "SaveImage"}, {"inputs", {{"image", {{"from", "blend.image"}}}, {"path", "blend.png"}}}}}}}};
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_engine_cache",
                       "Disk cache read throughput by entry size; first against second `loom run` with the "
                       "cache (2048² Poisson blend, ~100k-face ARAP); runs of the static part of a "
                       "240-frame graph.");
  bool quick = false;
  cli.quick(quick, "smaller sizes");
  cli.parse(argc, argv);
  const fs::path work = fs::temp_directory_path() / ("loom-bench-cache-" + std::to_string(::getpid()));
  fs::remove_all(work);

  // 1. Read throughput against size.
  loom::bench::Csv reads("engine_cache_read", {"megabytes", "write_seconds", "read_seconds", "read_mb_per_s"});
  {
    loom::DiskCache::Options o;
    o.dir = work / "throughput";
    loom::DiskCache cache(o);
    std::uint64_t key = 1;
    for (double mb : quick ? std::vector<double>{0.001, 1, 16} : std::vector<double>{0.001, 0.016, 0.25, 1, 4, 16, 64, 256}) {
      const auto n = static_cast<std::size_t>(mb * 1024 * 1024 / sizeof(double));
      const loom::Value v = loom::Value::make(std::vector<double>(n, 0.5));
      const auto w = loom::bench::time_median([&] { cache.store(key, {v}); }, 3);
      const auto r = loom::bench::time_median([&] {
        if (!cache.load(key)) std::exit(1);
      }, 5);
      reads.row({mb, w.median, r.median, mb / r.median});
      ++key;
    }
  }
  reads.save();
  loom::bench::plot(reads, {"megabytes", "read_seconds", "", "Disk cache: read time of one entry", true, true, ""});

  // 2. First against second run.
  loom::bench::Csv runs("engine_cache_runs",
                        {"graph", "node", "first_run_s", "second_run_s", "run_ratio", "node_compute_s",
                         "disk_read_s", "disk_mb", "node_ratio", "read_mb_per_s"});
  struct Case {
    std::string name, node;
    json graph;
  };
  std::vector<Case> cases = {
      {quick ? "poisson-1024" : "poisson-2048", "blend", poisson_graph(quick ? 1024 : 2048)},
      {quick ? "arap-25k" : "arap-100k", "arap", quick ? arap_graph(80, 160) : arap_graph(160, 320)}};
  for (const Case& c : cases) {
    const fs::path dir = work / c.name;
    const fs::path g = write_graph(dir, "g.json", c.graph);
    const std::string args = "--target " + c.node + " --cache " + (dir / "cache").string();
    auto [first, p1] = run(g, args, dir);
    auto [second, p2] = run(g, args, dir);
    if (p2["nodes"][c.node].value("source", "") != "disk") {
      std::cerr << c.name << ": the second run did not read " << c.node << " from disk\n";
      return 1;
    }
    const double compute = p1["nodes"][c.node]["seconds"].get<double>();
    const double read = p2["disk_cache"]["read_seconds"].get<double>();
    const double mb = p2["disk_cache"]["bytes_read"].get<double>() / (1024.0 * 1024.0);
    runs.row({c.name, c.node, first, second, first / second, compute, read, mb, compute / read, mb / read});
  }
  runs.save();

  // 3. 240 frames, one cheap time-dependent chain.
  loom::bench::Csv frames("engine_time_static", {"frames", "blend_runs", "time_runs", "save_runs", "seconds"});
  {
    const fs::path dir = work / "time";
    const fs::path g = write_graph(dir, "g.json", time_graph());
    auto [seconds, p] = run(g, "--no-cache", dir);
    frames.row({static_cast<long long>(p["frames"].get<int>()), static_cast<long long>(p["nodes"]["blend"]["runs"].get<int>()),
                static_cast<long long>(p["nodes"]["time"]["runs"].get<int>()),
                static_cast<long long>(p["nodes"]["save"]["runs"].get<int>()), seconds});
  }
  frames.save();

  // 4. What one copy of a simulation state costs (a step makes one per frame):
  // 1M particles with position and velocity, as two #P×3 double matrices.
  loom::bench::Csv copies("engine_state_copy", {"particles", "megabytes", "copy_seconds"});
  for (int n : quick ? std::vector<int>{100000} : std::vector<int>{100000, 1000000}) {
    struct State {
      Eigen::MatrixX3d x, v;
    };
    const State s{Eigen::MatrixX3d::Random(n, 3), Eigen::MatrixX3d::Random(n, 3)};
    State sink;
    const auto t = loom::bench::time_median([&] { sink = s; }, 9);
    copies.row({static_cast<long long>(n), 48.0 * n / (1024 * 1024), t.median});
  }
  copies.save();
  fs::remove_all(work);
  return 0;
}
