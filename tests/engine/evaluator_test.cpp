// The evaluator: pruning, laziness, caching, parallelism, failure isolation,
// cancellation, seeds.
#include <atomic>
#include <mutex>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

// Records which nodes' bodies ran.
struct RunLog : Observer {
  std::mutex mutex;
  std::multiset<std::string> started;
  void node_started(const std::string& id, const std::string&) override {
    std::lock_guard lock(mutex);
    started.insert(id);
  }
  int count(const std::string& id) {
    std::lock_guard lock(mutex);
    return static_cast<int>(started.count(id));
  }
};

json graph(json nodes) { return {{"loom", 1}, {"seed", 7}, {"nodes", std::move(nodes)}}; }
json from(const std::string& link) { return {{"from", link}}; }

EvalResult evaluate(testing::Engine& e, const Graph& g, std::vector<std::string> targets, RunLog* log, int threads = 0,
                    const std::atomic<bool>* cancel = nullptr) {
  EvalOptions o;
  for (const auto& t : targets) o.targets.push_back(parse_target(t));
  o.observer = log;
  o.threads = threads;
  o.cancel = cancel;
  o.output_dir = test::temp_dir();
  return e.session().evaluate(g, o);
}

double number(const EvalResult& r, const std::string& target) { return r.outputs.at(target).at(0).as<double>(); }

TEST(Evaluator, PrunesWhatTheTargetsDoNotNeed) {
  testing::Engine e;
  Graph g = e.load(graph({{"a", {{"type", "Math"}, {"inputs", {{"a", 1}, {"b", 2}}}}},
                          {"b", {{"type", "Math"}, {"inputs", {{"a", from("a.result")}, {"b", 10}}}}},
                          {"unused", {{"type", "Math"}, {"inputs", {{"a", 5}}}}}}));
  RunLog log;
  EvalResult r = evaluate(e, g, {"b.result"}, &log);
  EXPECT_DOUBLE_EQ(number(r, "b.result"), 13.0);
  EXPECT_EQ(r.nodes.at("unused").status, NodeStatus::pruned);
  EXPECT_EQ(log.count("unused"), 0);
  EXPECT_EQ(r.nodes.at("a").status, NodeStatus::ran);
}

TEST(Evaluator, SwitchNeverRunsTheUnselectedBranch) {
  testing::Engine e;
  Graph g = e.load(graph({{"cheap", {{"type", "FloatConstant"}, {"inputs", {{"value", 1}}}}},
                          {"costly", {{"type", "Sleep"}, {"inputs", {{"value", 2}, {"ms", 1}}}}},
                          {"broken", {{"type", "Fail"}}},
                          {"sw",
                           {{"type", "Switch"},
                            {"inputs",
                             {{"index", 0},
                              {"in0", from("cheap.value")},
                              {"in1", from("costly.value")},
                              {"in2", from("broken.value")}}}}}}));
  RunLog log;
  EvalResult r = evaluate(e, g, {"sw.value"}, &log);
  EXPECT_DOUBLE_EQ(number(r, "sw.value"), 1.0);
  EXPECT_EQ(log.count("costly"), 0);
  EXPECT_EQ(log.count("broken"), 0);
  EXPECT_EQ(r.nodes.at("costly").status, NodeStatus::pruned);
  EXPECT_TRUE(r.ok());

  set_input(g, "sw.index=1");
  r = evaluate(e, g, {"sw.value"}, &log);
  EXPECT_DOUBLE_EQ(number(r, "sw.value"), 2.0);
  EXPECT_EQ(log.count("costly"), 1);

  set_input(g, "sw.index=2");  // the selected branch fails: Switch is skipped, not failed
  r = evaluate(e, g, {"sw.value"}, &log);
  EXPECT_EQ(r.nodes.at("broken").status, NodeStatus::failed);
  EXPECT_EQ(r.nodes.at("sw").status, NodeStatus::skipped);
}

TEST(Evaluator, CacheHitsAfterAnUnrelatedChangeAndMissesAfterARelatedOne) {
  testing::Engine e;
  Graph g =
      e.load(graph({{"x", {{"type", "Math"}, {"inputs", {{"a", 1}, {"b", 2}}}}},
                    {"y", {{"type", "Math"}, {"inputs", {{"a", from("x.result")}, {"b", 3}}}}},
                    {"z", {{"type", "Math"}, {"inputs", {{"a", 100}, {"b", 1}}}}},
                    {"sum", {{"type", "Math"}, {"inputs", {{"a", from("y.result")}, {"b", from("z.result")}}}}}}));
  RunLog first;
  EvalResult r = evaluate(e, g, {"sum.result"}, &first);
  EXPECT_DOUBLE_EQ(number(r, "sum.result"), 107.0);
  EXPECT_EQ(first.started.size(), 4u);

  RunLog again;  // nothing changed: the target itself is a hit, nothing runs
  r = evaluate(e, g, {"sum.result"}, &again);
  EXPECT_EQ(again.started.size(), 0u);
  EXPECT_EQ(r.nodes.at("sum").status, NodeStatus::cached);
  EXPECT_EQ(r.nodes.at("x").status, NodeStatus::pruned);  // a hit needs none of its inputs

  set_input(g, "z.b=2");  // related to z and sum only
  RunLog changed;
  r = evaluate(e, g, {"sum.result"}, &changed);
  EXPECT_DOUBLE_EQ(number(r, "sum.result"), 108.0);
  EXPECT_EQ(changed.count("z"), 1);
  EXPECT_EQ(changed.count("sum"), 1);
  EXPECT_EQ(changed.count("x"), 0);
  EXPECT_EQ(changed.count("y"), 0);
  EXPECT_EQ(r.nodes.at("y").status, NodeStatus::cached);
}

TEST(Evaluator, ChangingTheNodeTypeVersionOrDefaultsMissesTheCache) {
  testing::Engine e;
  Graph a = e.load(graph({{"m", {{"type", "Math"}, {"inputs", {{"a", 1}, {"b", 2}}}}}}));
  Graph b = e.load(graph({{"m", {{"type", "Math"}, {"inputs", {{"a", 1}, {"b", 2}, {"op", "add"}}}}}}));
  RunLog l1, l2;
  evaluate(e, a, {"m"}, &l1);
  evaluate(e, b, {"m"}, &l2);  // the same values, one written, one by default: one computation
  EXPECT_EQ(l2.count("m"), 0);
}

TEST(Evaluator, NondeterministicNodesAndTheirDependentsAreNeverCached) {
  testing::Engine e;
  Graph g =
      e.load(graph({{"t", {{"type", "Clockwork"}}}, {"m", {{"type", "Math"}, {"inputs", {{"a", from("t.value")}}}}}}));
  RunLog l1, l2;
  evaluate(e, g, {"m"}, &l1);
  evaluate(e, g, {"m"}, &l2);
  EXPECT_EQ(l2.count("t"), 1);
  EXPECT_EQ(l2.count("m"), 1);
}

TEST(Evaluator, IndependentNodesRunInParallel) {
  testing::Engine e;
  // Each Rendezvous fails unless the other runs at the same time.
  Graph g =
      e.load(graph({{"r1", {{"type", "Rendezvous"}, {"inputs", {{"tag", 1}}}}},
                    {"r2", {{"type", "Rendezvous"}, {"inputs", {{"tag", 2}}}}},
                    {"sum", {{"type", "Math"}, {"inputs", {{"a", from("r1.value")}, {"b", from("r2.value")}}}}}}));
  EvalResult r = evaluate(e, g, {"sum.result"}, nullptr, 2);
  EXPECT_TRUE(r.ok()) << r.nodes.at("r1").error;
  EXPECT_DOUBLE_EQ(number(r, "sum.result"), 2.0);
}

TEST(Evaluator, OneThreadRunsNodesOneAtATime) {
  testing::Engine e;
  Graph g =
      e.load(graph({{"r1", {{"type", "Rendezvous"}, {"inputs", {{"tag", 3}, {"timeout_ms", 200}}}}},
                    {"r2", {{"type", "Rendezvous"}, {"inputs", {{"tag", 4}, {"timeout_ms", 200}}}}},
                    {"sum", {{"type", "Math"}, {"inputs", {{"a", from("r1.value")}, {"b", from("r2.value")}}}}}}));
  EvalResult r = evaluate(e, g, {"sum.result"}, nullptr, 1);
  EXPECT_FALSE(r.ok());  // --threads 1 is a real bound: they cannot meet
}

TEST(Evaluator, AFailureSkipsDependentsAndIndependentSinksFinish) {
  testing::Engine e;
  auto dir = test::temp_dir();
  Graph g = e.load(
      graph({{"bad", {{"type", "Fail"}}},
             {"after", {{"type", "Math"}, {"inputs", {{"a", from("bad.value")}}}}},
             {"sink1", {{"type", "WriteText"}, {"inputs", {{"value", from("after.result")}, {"path", "a.txt"}}}}},
             {"good", {{"type", "FloatConstant"}, {"inputs", {{"value", 4}}}}},
             {"sink2", {{"type", "WriteText"}, {"inputs", {{"value", from("good.value")}, {"path", "b.txt"}}}}}}));
  testing::Run r = e.run(g, {}, dir);
  EXPECT_EQ(r.status("bad"), NodeStatus::failed);
  EXPECT_EQ(r.error("bad"), "failing on purpose");
  EXPECT_EQ(r.status("after"), NodeStatus::skipped);
  EXPECT_EQ(r.status("sink1"), NodeStatus::skipped);
  EXPECT_EQ(r.status("sink2"), NodeStatus::ran);
  EXPECT_TRUE(std::filesystem::exists(dir / "b.txt"));
  EXPECT_FALSE(std::filesystem::exists(dir / "a.txt"));
  EXPECT_FALSE(r.ok());
}

TEST(Evaluator, NoNaNOrInfinityLeavesANode) {
  testing::Engine e;
  Graph g = e.load(graph({{"nan", {{"type", "UncheckedRatio"}, {"inputs", {{"a", 0}, {"b", 0}}}}},
                          {"inf", {{"type", "UncheckedRatio"}, {"inputs", {{"a", 1}, {"b", 0}}}}},
                          {"fine", {{"type", "UncheckedRatio"}, {"inputs", {{"a", 1}, {"b", 4}}}}},
                          {"after", {{"type", "Math"}, {"inputs", {{"a", from("nan.value")}}}}}}));
  EvalResult r = evaluate(e, g, {"after.result", "inf.points", "fine.value"}, nullptr);
  EXPECT_EQ(r.nodes.at("nan").status, NodeStatus::failed);
  EXPECT_EQ(r.nodes.at("nan").error, "output \"value\": the number is NaN or infinite");
  EXPECT_EQ(r.nodes.at("inf").status, NodeStatus::failed);
  EXPECT_EQ(r.nodes.at("after").status, NodeStatus::skipped);
  EXPECT_EQ(r.nodes.at("fine").status, NodeStatus::ran);
  EXPECT_DOUBLE_EQ(number(r, "fine.value"), 0.25);
}

TEST(Evaluator, SinksAlwaysRun) {
  testing::Engine e;
  auto dir = test::temp_dir();
  Graph g =
      e.load(graph({{"v", {{"type", "FloatConstant"}, {"inputs", {{"value", 1}}}}},
                    {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("v.value")}, {"path", "v.txt"}}}}}}));
  e.run(g, {}, dir);
  std::filesystem::remove(dir / "v.txt");
  testing::Run r = e.run(g, {}, dir);
  EXPECT_EQ(r.status("w"), NodeStatus::ran);
  EXPECT_EQ(r.status("v"), NodeStatus::cached);
  EXPECT_TRUE(std::filesystem::exists(dir / "v.txt"));
}

TEST(Evaluator, CancellationStopsARunningNodeAndIsNotCached) {
  testing::Engine e;
  Graph g = e.load(graph({{"slow", {{"type", "Sleep"}, {"inputs", {{"ms", 20000}}}}},
                          {"after", {{"type", "Math"}, {"inputs", {{"a", from("slow.value")}}}}}}));
  std::atomic<bool> cancel{false};
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    cancel = true;
  });
  auto start = std::chrono::steady_clock::now();
  EvalResult r = evaluate(e, g, {"after"}, nullptr, 0, &cancel);
  canceller.join();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  EXPECT_TRUE(r.cancelled);
  EXPECT_EQ(r.nodes.at("slow").status, NodeStatus::failed);
  EXPECT_EQ(r.nodes.at("slow").error, "cancelled");
  EXPECT_EQ(r.nodes.at("after").status, NodeStatus::skipped);
  EXPECT_EQ(e.session().cache_entries(), 0u);
}

TEST(Evaluator, SeedsComeFromTheGraphSeedAndNodeIdNotFromOrder) {
  auto value = [](std::uint64_t seed, const std::string& id, int threads) {
    testing::Engine e;
    json doc = graph({{id, {{"type", "Random"}}}, {"other", {{"type", "Random"}}}});
    doc["seed"] = seed;
    Graph g = e.load(doc);
    return number(evaluate(e, g, {id + ".value", "other.value"}, nullptr, threads), id + ".value");
  };
  EXPECT_EQ(value(7, "r", 1), value(7, "r", 2));
  EXPECT_NE(value(7, "r", 1), value(8, "r", 1));
  EXPECT_NE(value(7, "r", 1), value(7, "s", 1));
}

TEST(Evaluator, EqualNodesWithDifferentIdsDoNotShareSeededResults) {
  testing::Engine e;
  Graph g = e.load(graph({{"r", {{"type", "Random"}}}, {"s", {{"type", "Random"}}}}));
  EvalResult r = evaluate(e, g, {"r.value", "s.value"}, nullptr);
  EXPECT_NE(number(r, "r.value"), number(r, "s.value"));
}

TEST(Evaluator, ALongChainDoesNotRecurse) {
  testing::Engine e;
  json nodes = json::object();
  nodes["n0"] = {{"type", "FloatConstant"}, {"inputs", {{"value", 0}}}};
  const int n = 20000;
  for (int i = 1; i < n; ++i)
    nodes["n" + std::to_string(i)] = {{"type", "Math"},
                                      {"inputs", {{"a", from("n" + std::to_string(i - 1) + ".result")}, {"b", 1}}}};
  nodes["n1"]["inputs"]["a"] = from("n0.value");
  Graph g = e.load(graph(nodes));
  EvalResult r = evaluate(e, g, {"n" + std::to_string(n - 1) + ".result"}, nullptr);
  EXPECT_DOUBLE_EQ(number(r, "n" + std::to_string(n - 1) + ".result"), n - 1.0);
}

}  // namespace
}  // namespace loom

namespace loom {
namespace {

// Progress reported from worker threads reaches the observer in order:
// monotone per label, never more than ~100 reports plus the final one.
struct RecordingObserver : Observer {
  std::mutex mutex;
  std::vector<double> fractions;
  int warnings = 0;
  void node_progress(const std::string&, double fraction, const std::string&) override {
    std::lock_guard lock(mutex);
    fractions.push_back(fraction);
  }
  void node_message(const std::string&, bool warning, const std::string&) override {
    std::lock_guard lock(mutex);
    warnings += warning;
  }
};

TEST(Evaluator, ProgressFromWorkerThreadsIsMonotone) {
  testing::Engine engine;
  auto g = engine.load({{"loom", 1}, {"nodes", {{"p", {{"type", "ParallelProgress"}}}}}});
  RecordingObserver observer;
  EvalOptions options;
  options.targets = {parse_target("p")};
  options.observer = &observer;
  options.threads = 4;
  auto r = engine.session().evaluate(g, options);
  ASSERT_EQ(r.nodes.at("p").status, NodeStatus::ran) << r.nodes.at("p").error;
  ASSERT_FALSE(observer.fractions.empty());
  for (std::size_t i = 1; i < observer.fractions.size(); ++i)
    EXPECT_GT(observer.fractions[i], observer.fractions[i - 1]);
  EXPECT_LE(observer.fractions.size(), 102u);
  EXPECT_EQ(observer.fractions.back(), 1.0);
  EXPECT_EQ(observer.warnings, 4);
  EXPECT_EQ(r.nodes.at("p").warnings.size(), 4u);
}

}  // namespace
}  // namespace loom
