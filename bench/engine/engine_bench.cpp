// Engine overhead: a chain of N trivial nodes (Math: a + 1) evaluated cold, then
// fully cached; and `loom run` start-up for a one-node graph, with lazy plugin
// loading (only util) against a graph that needs OpenCV (generate) and against
// loading every plugin (`loom nodes`).
//
// Targets (issue 2): under 2 µs per node, start-up under 30 ms.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>

#include "bench_harness.hpp"
#include "loom/evaluator.hpp"
#include "loom/plugin_loader.hpp"

namespace {

using loom::json;

json chain(int n) {
  json nodes = json::object();
  nodes["n0"] = {{"type", "FloatConstant"}, {"inputs", {{"value", 0}}}};
  for (int i = 1; i < n; ++i)
    nodes["n" + std::to_string(i)] = {
        {"type", "Math"},
        {"inputs", {{"a", {{"from", "n" + std::to_string(i - 1) + (i == 1 ? ".value" : ".result")}}}, {"b", 1}}}};
  return {{"loom", 1}, {"nodes", nodes}};
}

double seconds_of(const std::string& command, int runs) {
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    auto start = std::chrono::steady_clock::now();
    if (std::system(command.c_str()) != 0) {
      std::cerr << "command failed: " << command << "\n";
      std::exit(1);
    }
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_engine",
                       "Engine overhead: chains of N Math nodes (cold and fully cached, 1 and 2 threads) and "
                       "`loom run` start-up with lazy and eager plugin loading.");
  bool quick = false;
  cli.quick(quick, "fewer sizes and runs");
  cli.parse(argc, argv);
  loom::Registry registry;
  loom::PluginLoader loader(registry, {LOOM_PLUGIN_DIR});
  loader.load_for({"Math", "FloatConstant"});

  loom::bench::Csv csv("engine_chain", {"nodes", "threads", "phase", "seconds", "us_per_node"});
  for (int n : quick ? std::vector<int>{1000, 10000} : std::vector<int>{1000, 3000, 10000, 30000}) {
    loom::Graph g = loom::parse_graph(chain(n), "chain.json");
    loom::validate_graph(g, registry);
    const std::string target = "n" + std::to_string(n - 1) + ".result";
    for (int threads : {1, 2}) {
      loom::EvalOptions o;
      o.targets = {loom::parse_target(target)};
      o.threads = threads;
      auto cold = loom::bench::time_median([&] { loom::Session(registry).evaluate(g, o); }, quick ? 3 : 5);
      loom::Session warm(registry);
      warm.evaluate(g, o);
      auto cached = loom::bench::time_median([&] { warm.evaluate(g, o); }, quick ? 3 : 5);
      csv.row({static_cast<long long>(n), static_cast<long long>(threads), std::string("cold"), cold.median,
               cold.median / n * 1e6});
      csv.row({static_cast<long long>(n), static_cast<long long>(threads), std::string("cached"), cached.median,
               cached.median / n * 1e6});
    }
  }
  csv.save();
  loom::bench::plot(csv, {"nodes", "us_per_node", "phase", "Engine overhead per node (chain of Math nodes)",
                          true, false, ""});

  // Start-up of the runner, one-node graphs.
  const std::string dir = std::filesystem::temp_directory_path() / "loom-bench-startup";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/util.json") << R"({"loom": 1, "nodes": {"m": {"type": "Math", "inputs": {"a": 1}}}})";
  std::ofstream(dir + "/opencv.json")
      << R"({"loom": 1, "nodes": {"b": {"type": "Checkerboard", "inputs": {"size": [8, 8]}}}})";
  const std::string loom = LOOM_RUNNER;
  const int runs = quick ? 5 : 21;
  loom::bench::Csv startup("engine_startup", {"case", "seconds"});
  startup.row({std::string("one util node (lazy loading)"),
               seconds_of(loom + " run " + dir + "/util.json -q --target m > /dev/null", runs)});
  startup.row({std::string("one OpenCV node (loads generate)"),
               seconds_of(loom + " run " + dir + "/opencv.json -q --target b > /dev/null", runs)});
  startup.row({std::string("every plugin (loom nodes)"), seconds_of(loom + " nodes > /dev/null", runs)});
  startup.save();
  return 0;
}
