// Partial results (Context::publish_partial): they reach the observer that
// asks for them and nothing else — not the cache, not a sink, not a node
// downstream — and a node builds none when nobody listens. The fixture Refine
// publishes 1, 2, …, passes-1 and ends with `passes`, so a partial value that
// leaked anywhere would be told apart from the result by its value.
#include <mutex>
#include <vector>

#include <gtest/gtest.h>

#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

struct Published {
  std::string node, output;
  double value = 0, done = 0, total = 0;
  std::string unit;
};

// Listens to every node (or to none) and records what it is handed.
struct PartialLog : Observer {
  explicit PartialLog(bool listen = true) : listen(listen) {}
  bool listen;
  std::mutex mutex;
  std::vector<Published> published;
  bool wants_partial(const std::string&) const override { return listen; }
  void node_partial(const std::string& id, const std::string& output, const Value& value,
                    const PartialInfo& info) override {
    std::lock_guard lock(mutex);
    published.push_back({id, output, value.as<double>(), info.done, info.total, std::string(info.unit)});
  }
};

json graph(json nodes) { return {{"loom", 1}, {"seed", 7}, {"nodes", std::move(nodes)}}; }
json from(const std::string& link) { return {{"from", link}}; }

// Refine (5 passes) → Math (+ 10) → WriteText, and Refine → WriteText.
json refine_chain() {
  return graph({{"r", {{"type", "Refine"}, {"inputs", {{"passes", 5}}}}},
                {"m", {{"type", "Math"}, {"inputs", {{"a", from("r.value")}, {"b", 10}}}}},
                {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("m.result")}, {"path", "m.txt"}}}}},
                {"wr", {{"type", "WriteText"}, {"inputs", {{"value", from("r.value")}, {"path", "r.txt"}}}}}});
}

EvalResult run(testing::Engine& e, const Graph& g, Observer* observer, const std::filesystem::path& out,
               std::vector<std::string> targets = {}) {
  EvalOptions o;
  for (const auto& t : targets) o.targets.push_back(parse_target(t));
  o.observer = observer;
  o.output_dir = out;
  return e.session().evaluate(g, o);
}

TEST(Partials, ReachTheObserverButNeitherTheCacheNorSinksNorDownstreamNodes) {
  testing::Engine e;
  const Graph g = e.load(refine_chain());
  const auto out = test::temp_dir();
  PartialLog log;
  EvalResult r = run(e, g, &log, out, {"w", "wr", "m.result", "r.value"});
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(log.published.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(log.published[k].node, "r");
    EXPECT_EQ(log.published[k].output, "value");
    EXPECT_EQ(log.published[k].value, k + 1);
    EXPECT_EQ(log.published[k].done, k + 1);
    EXPECT_EQ(log.published[k].total, 5);
    EXPECT_EQ(log.published[k].unit, "passes");
  }
  // Downstream and the sinks saw the result only.
  EXPECT_EQ(r.outputs.at("r.value")[0].as<double>(), 5);
  EXPECT_EQ(r.outputs.at("m.result")[0].as<double>(), 15);
  EXPECT_EQ(test::read_text(out / "m.txt"), "15.000000\n");
  EXPECT_EQ(test::read_text(out / "r.txt"), "5.000000\n");
  // The cache holds the result: a second run serves it, publishing nothing.
  PartialLog again;
  r = run(e, g, &again, out, {"m.result", "r.value"});
  EXPECT_EQ(r.nodes.at("r").status, NodeStatus::cached);
  EXPECT_EQ(r.outputs.at("r.value")[0].as<double>(), 5);
  EXPECT_EQ(r.outputs.at("m.result")[0].as<double>(), 15);
  EXPECT_TRUE(again.published.empty());
}

TEST(Partials, NothingIsBuiltWhenNobodyListens) {
  const auto out = test::temp_dir();
  auto built = [&](Observer* observer) {
    testing::Engine e;  // a session of its own: no cache shared between the cases
    const EvalResult r = run(e, e.load(refine_chain()), observer, out, {"r.built", "r.value"});
    EXPECT_EQ(r.outputs.at("r.value")[0].as<double>(), 5);
    return r.outputs.at("r.built")[0].as<int>();
  };
  PartialLog deaf(false), listening(true);
  EXPECT_EQ(built(nullptr), 0);
  EXPECT_EQ(built(&deaf), 0);
  EXPECT_TRUE(deaf.published.empty());
  EXPECT_EQ(built(&listening), 4);
}

}  // namespace
}  // namespace loom
