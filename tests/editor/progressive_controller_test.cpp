// The controller and partial results: the running evaluation's newest partial
// value is there to show while it runs; a new request cancels it, and from the
// first partial of the new run on nothing of the old graph runs or shows.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "controller/evaluation_controller.hpp"
#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom::editor {
namespace {

using Clock = std::chrono::steady_clock;

// Refine: `passes` passes of `ms` each, publishing 1, 2, … and ending with `passes`.
json refine(const std::string& id, int passes, int ms) {
  return {{"loom", 1}, {"nodes", {{id, {{"type", "Refine"}, {"inputs", {{"passes", passes}, {"ms", ms}}}}}}}};
}

EvalRequest request(json doc, std::uint64_t revision, const std::string& target) {
  EvalRequest r;
  r.document = std::move(doc);
  r.file = test::temp_dir() / "g.json";
  r.output_dir = r.file.parent_path();
  r.revision = revision;
  r.targets.push_back(parse_target(target));
  return r;
}

// Polls until `node`.value has a partial of `revision`; its arrival time.
std::optional<Clock::time_point> await_partial(const EvaluationController& c, const std::string& node,
                                               std::uint64_t revision, double timeout = 10) {
  const auto start = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - start).count() < timeout) {
    if (auto p = c.partial(node, "value"); p && p->revision == revision) return Clock::now();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return std::nullopt;
}

TEST(ProgressiveController, TheNewestPartialIsThereWhileTheRunLastsAndTheResultEndsIt) {
  testing::Engine engine;
  engine.load_plugins({"Refine"});
  EvaluationController controller(engine.registry(), 2);
  controller.submit(request(refine("r", 40, 10), 1, "r.value"));
  ASSERT_TRUE(await_partial(controller, "r", 1));
  EXPECT_TRUE(controller.refining());
  double last = 0;
  for (int i = 0; i < 20; ++i) {  // the passes come in order, each newer than the last
    const auto p = controller.partial("r", "value");
    ASSERT_TRUE(p);
    EXPECT_GE(p->value.as<double>(), last);
    EXPECT_LT(p->value.as<double>(), 40);  // never the result
    EXPECT_EQ(p->done, p->value.as<double>());
    EXPECT_EQ(p->total, 40);
    last = p->value.as<double>();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_GT(last, 1);
  controller.wait_idle();
  EXPECT_FALSE(controller.refining());
  auto done = controller.take_finished();
  ASSERT_TRUE(done);
  EXPECT_EQ((*done)->result.outputs.at("r.value").at(0).as<double>(), 40);
}

TEST(ProgressiveController, CancelAndRestartLeavesNothingOfTheOldGraphRunning) {
  testing::Engine engine;
  engine.load_plugins({"Refine"});
  EvaluationController controller(engine.registry(), 2);
  controller.submit(request(refine("old", 1000, 20), 1, "old.value"));  // 20 s
  ASSERT_TRUE(await_partial(controller, "old", 1));
  const auto submitted = Clock::now();
  controller.submit(request(refine("new", 1000, 20), 2, "new.value"));
  const auto first = await_partial(controller, "new", 2);
  ASSERT_TRUE(first);
  const double latency = std::chrono::duration<double>(*first - submitted).count();
  std::printf("submit -> first partial of the new run: %.1f ms (a pass is 20 ms)\n", latency * 1e3);
  EXPECT_LT(latency, 0.5);
  // From then on the old node neither runs (it would show in live()) nor publishes.
  const auto watch = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - watch).count() < 0.5) {
    EXPECT_FALSE(controller.partial("old", "value"));
    EXPECT_EQ(controller.live().count("old"), 0u);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(controller.live().count("new"), 1u);
  controller.cancel();
  controller.wait_idle();
}

}  // namespace
}  // namespace loom::editor
