// Groups: engine overhead per inner node against the same chain written flat,
// and load + validate time of graphs built from groups. A chain of N Math
// nodes (a + 1) is written three ways: flat (version 1), as N/10 instances of
// an inline group of 10 chained nodes, and nested (N/100 instances of a group
// of 10 instances of that group). Each case is timed alternately with its
// flat peer (medians), so machine load spoils both alike; ratios are printed.
#include <iostream>

#include "bench_harness.hpp"
#include "loom/evaluator.hpp"
#include "loom/plugin_loader.hpp"

namespace {

using loom::json;
using loom::bench::median;

json link(const std::string& from) { return {{"from", from}}; }

json flat(int n) {
  json nodes = json::object();
  nodes["n0"] = {{"type", "FloatConstant"}, {"inputs", {{"value", 0}}}};
  for (int i = 1; i <= n; ++i)
    nodes["n" + std::to_string(i)] = {
        {"type", "Math"}, {"inputs", {{"a", link("n" + std::to_string(i - 1) + (i == 1 ? ".value" : ".result"))}, {"b", 1}}}};
  return {{"loom", 1}, {"nodes", nodes}};
}

// A group of 10 chained `inner` (Math, or another group): x -> x + 10.
json ten_of(const std::string& inner, const std::string& in, const std::string& out) {
  json nodes = json::object();
  for (int i = 0; i < 10; ++i) {
    json inputs = i == 0 ? json::object() : json{{in, link("s" + std::to_string(i - 1) + "." + out)}};
    if (inner == "Math") inputs["b"] = 1;
    nodes["s" + std::to_string(i)] = {{"type", inner}, {"inputs", inputs}};
  }
  return {{"inputs", {{"x", {{"type", "Float"}, {"default", 0}, {"to", {"s0." + in}}}}}},
          {"outputs", {{"x", {{"from", "s9." + out}}}}},
          {"nodes", nodes}};
}

// N Math nodes as a chain of N / size instances of `group`.
json grouped(int n, bool nested) {
  const int size = nested ? 100 : 10;
  const std::string group = nested ? "Hundred" : "Ten";
  json nodes = json::object();
  nodes["n0"] = {{"type", "FloatConstant"}, {"inputs", {{"value", 0}}}};
  for (int i = 1; i <= n / size; ++i)
    nodes["g" + std::to_string(i)] = {
        {"type", group}, {"inputs", {{"x", link(i == 1 ? "n0.value" : "g" + std::to_string(i - 1) + ".x")}}}};
  json groups = {{"Ten", ten_of("Math", "a", "result")}};
  if (nested) groups["Hundred"] = ten_of("Ten", "x", "x");
  return {{"loom", 2}, {"groups", groups}, {"nodes", nodes}};
}

struct Case {
  std::string form;
  json doc;
  std::string target;
};

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_engine_groups",
                       "Groups: per-node engine overhead (cold, cached) and load + validate time, against flat chains.");
  bool quick = false;
  int only = -1, only_nodes = 1000;
  cli.quick(quick, "fewer sizes and runs");
  cli.option("--only", only,
             "for instruction counts (valgrind --tool=callgrind): load, validate and evaluate once the chain of "
             "--nodes as 0 nothing, 1 flat, 2 groups of 10, 3 nested 10x10; no CSV");
  cli.option("--nodes", only_nodes, "with --only: chain length (a multiple of 100)");
  cli.parse(argc, argv);
  loom::Registry registry;
  loom::PluginLoader loader(registry, {LOOM_PLUGIN_DIR});
  loader.load_for({"Math", "FloatConstant"});
  if (only >= 0) {
    const int n = only_nodes;
    const std::vector<Case> cases = {{"flat", flat(n), "n" + std::to_string(n) + ".result"},
                                     {"groups of 10", grouped(n, false), "g" + std::to_string(n / 10) + ".s9.result"},
                                     {"nested 10x10", grouped(n, true), "g" + std::to_string(n / 100) + ".s9.s9.result"}};
    if (only == 0) return 0;
    const Case& c = cases.at(static_cast<std::size_t>(only - 1));
    loom::Graph g = loom::parse_graph(c.doc, "chain.json");
    loom::validate_graph(g, registry);
    loom::EvalOptions o;
    o.targets = {loom::parse_target(c.target)};
    o.threads = 1;
    loom::Session(registry).evaluate(g, o);
    return 0;
  }
  const int runs = quick ? 5 : 11;

  loom::bench::Csv csv("engine_groups", {"nodes", "form", "phase", "seconds", "us_per_node", "ratio_to_flat"});
  for (int n : quick ? std::vector<int>{1000} : std::vector<int>{1000, 10000}) {
    const std::string last = std::to_string(n / 10), last100 = std::to_string(n / 100);
    std::vector<Case> cases = {{"flat", flat(n), "n" + std::to_string(n) + ".result"},
                               {"groups of 10", grouped(n, false), "g" + last + ".s9.result"},
                               {"nested 10x10", grouped(n, true), "g" + last100 + ".s9.s9.result"}};
    std::vector<loom::Graph> graphs;
    std::map<std::string, std::vector<double>> t;  // form/phase -> times, alternating forms
    for (int r = 0; r < runs; ++r)
      for (const Case& c : cases) {
        auto start = std::chrono::steady_clock::now();
        loom::Graph g = loom::parse_graph(c.doc, "chain.json");
        loom::validate_graph(g, registry);
        auto loaded = std::chrono::steady_clock::now();
        loom::EvalOptions o;
        o.targets = {loom::parse_target(c.target)};
        o.threads = 1;
        loom::Session session(registry);
        session.evaluate(g, o);
        auto cold = std::chrono::steady_clock::now();
        session.evaluate(g, o);
        auto cached = std::chrono::steady_clock::now();
        auto s = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
        t[c.form + "/load+validate"].push_back(s(start, loaded));
        t[c.form + "/cold"].push_back(s(loaded, cold));
        t[c.form + "/cached"].push_back(s(cold, cached));
      }
    for (const Case& c : cases)
      for (const std::string phase : {"load+validate", "cold", "cached"}) {
        const double m = median(t[c.form + "/" + phase]), f = median(t["flat/" + phase]);
        csv.row({static_cast<long long>(n), c.form, phase, m, m / n * 1e6, m / f});
        std::printf("%6d nodes  %-13s %-14s %9.3f ms  %6.3f us/node  x%.2f of flat\n", n, c.form.c_str(),
                    phase.c_str(), m * 1e3, m / n * 1e6, m / f);
      }
  }
  csv.save();
  loom::bench::plot(csv, {"nodes", "us_per_node", "form", "Engine overhead per node: flat chain vs groups", true, false, ""});
  return 0;
}
