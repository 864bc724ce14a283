// The time slider without a window: the frame kept in the graph's "ui"
// field, playback (cadence, dropping to the graph's rate, loop), and the
// controller's cached-frame marks (a simulation's frames stepped, dropped
// when a parameter upstream of it changes, kept for a downstream change).
#include <fstream>

#include "controller/evaluation_controller.hpp"
#include "loom/testing.hpp"
#include "model/graph_document.hpp"
#include "model/playback.hpp"
#include "test_files.hpp"

namespace loom::editor {
namespace {

struct TimeSliderTest : ::testing::Test {
  testing::Engine engine;
  void SetUp() override { engine.load_plugins({"Math", "Integrate"}); }
};

// x0 -> sim (x(f) = x(f-1) + v/fps) -> after; frames 1..10 at 24 fps.
json simulation(double x0, double v, double after_b) {
  return {{"loom", 1},
          {"time", {{"start", 1}, {"end", 10}, {"fps", 24}}},
          {"nodes",
           {{"x0", {{"type", "Math"}, {"inputs", {{"a", x0}, {"b", 0}}}}},
            {"sim", {{"type", "Integrate"}, {"inputs", {{"x", {{"from", "x0.result"}}}, {"v", v}, {"ms", 2}}}}},
            {"after", {{"type", "Math"}, {"inputs", {{"a", {{"from", "sim.x"}}}, {"b", after_b}}}}}}}};
}

std::vector<int> span(int first, int last) {
  std::vector<int> v;
  for (int f = first; f <= last; ++f) v.push_back(f);
  return v;
}

std::shared_ptr<const Evaluation> evaluate_at(EvaluationController& c, const json& doc, int frame,
                                              std::uint64_t revision) {
  EvalRequest r;
  r.document = doc;
  r.file = test::temp_dir() / "g.json";
  r.output_dir = r.file.parent_path();
  r.revision = revision;
  r.targets = {parse_target("sim"), parse_target("after")};
  r.frames = FrameRange{frame, frame};
  r.frames_of = "sim";
  c.submit(std::move(r));
  c.wait_idle();
  return c.latest();
}

TEST_F(TimeSliderTest, MarksAreTheSimulationFramesAndAnUpstreamEditDropsThem) {
  EvaluationController controller(engine.registry(), 2);
  auto e = evaluate_at(controller, simulation(1, 2, 0), 4, 1);
  ASSERT_TRUE(e->result.ok()) << e->error;
  EXPECT_EQ(e->frame, 4);
  // x(4) = x0 + v * 3 / fps, the closed form of the steps.
  EXPECT_NEAR(e->result.outputs.at("sim").at(0).as<double>(), 1 + 2 * 3 / 24.0, 1e-12);
  EXPECT_EQ(e->frames_of, "sim");
  EXPECT_EQ(e->cached_frames, span(1, 4));

  e = evaluate_at(controller, simulation(1, 2, 0), 7, 2);  // scrubbing on steps 5..7
  EXPECT_EQ(e->result.nodes.at("sim").runs, 3);
  EXPECT_EQ(e->cached_frames, span(1, 7));
  e = evaluate_at(controller, simulation(1, 2, 0), 2, 3);  // scrubbing back: a cache hit
  EXPECT_EQ(e->result.nodes.at("sim").status, NodeStatus::cached);
  EXPECT_NEAR(e->result.outputs.at("sim").at(0).as<double>(), 1 + 2 * 1 / 24.0, 1e-12);
  EXPECT_EQ(e->cached_frames, span(1, 7));

  // A downstream setting keeps the simulation's frames.
  e = evaluate_at(controller, simulation(1, 2, 5), 2, 4);
  EXPECT_EQ(e->result.nodes.at("sim").status, NodeStatus::cached);
  EXPECT_EQ(e->cached_frames, span(1, 7));
  // The initial state upstream changes: every mark goes but the frame shown.
  e = evaluate_at(controller, simulation(3, 2, 5), 2, 5);
  EXPECT_EQ(e->result.nodes.at("sim").status, NodeStatus::ran);
  EXPECT_NEAR(e->result.outputs.at("sim").at(0).as<double>(), 3 + 2 * 1 / 24.0, 1e-12);
  EXPECT_EQ(e->cached_frames, span(1, 2));
  // And a parameter of the simulation itself.
  e = evaluate_at(controller, simulation(3, 4, 5), 1, 6);
  EXPECT_EQ(e->cached_frames, span(1, 1));
}

TEST_F(TimeSliderTest, TheFrameIsKeptInTheGraphUiFieldAndIsNotAnEdit) {
  GraphDocument doc(engine.registry());
  doc.load_json(simulation(1, 2, 0), test::temp_dir() / "g.json");
  ASSERT_TRUE(doc.time_range());
  EXPECT_EQ(doc.time_range()->end, 10);
  EXPECT_EQ(doc.frame(), 1);  // unset: the start
  const auto revision = doc.revision();
  doc.set_frame(6);
  EXPECT_EQ(doc.frame(), 6);
  EXPECT_FALSE(doc.dirty());
  EXPECT_FALSE(doc.can_undo());
  EXPECT_EQ(doc.revision(), revision);
  EXPECT_FALSE(doc.evaluated_part().contains("ui"));
  doc.set_input("after", "b", 2.0);
  doc.set_frame(8);
  EXPECT_TRUE(doc.undo());
  EXPECT_EQ(doc.frame(), 8);  // undo is about edits, not where the slider is
  doc.set_frame(99);
  EXPECT_EQ(doc.frame(), 10);  // clamped to the range

  const auto file = test::temp_dir() / "framed.json";
  doc.set_frame(6);
  doc.save(file);
  GraphDocument reopened(engine.registry());
  reopened.load(file);
  EXPECT_EQ(reopened.frame(), 6);
  EXPECT_EQ(reopened.document()["ui"], (json{{"frame", 6}}));
  // The saved file is an ordinary graph: the engine reads it.
  EXPECT_NO_THROW(engine.load(reopened.document(), file));

  doc.load_json({{"loom", 1}, {"nodes", json::object()}});
  EXPECT_FALSE(doc.time_range());
  EXPECT_EQ(doc.frame(), 1);
}

TEST(Playback, KeepsTheGraphRateDropsToTheComputeRateAndLoops) {
  const TimeRange range{1, 5, 8};  // 0.125 s a frame (exact in binary)
  Playback p;
  int frame = 1;
  EXPECT_FALSE(p.tick(1.0, true, range, frame));  // not playing
  p.play(0.0, range, frame);
  EXPECT_FALSE(p.tick(0.0625, true, range, frame));  // too early
  EXPECT_EQ(p.tick(0.125, true, range, frame), 2);
  frame = 2;
  // The UI ticks at its own rate: the cadence stays 0.125 s, not "0.125 s
  // after the UI frame that moved".
  EXPECT_FALSE(p.tick(0.24, true, range, frame));
  EXPECT_EQ(p.tick(0.25, true, range, frame), 3);
  frame = 3;
  // The frame is not computed yet: wait, however late.
  EXPECT_FALSE(p.tick(0.9, false, range, frame));
  EXPECT_EQ(p.tick(1.0, true, range, frame), 4);  // late: from now on
  frame = 4;
  EXPECT_FALSE(p.tick(1.0625, true, range, frame));
  EXPECT_EQ(p.tick(1.125, true, range, frame), 5);
  frame = 5;
  EXPECT_EQ(p.tick(1.25, true, range, frame), 1);  // loops
  p.set_loop(false);
  frame = 5;
  EXPECT_FALSE(p.tick(1.375, true, range, frame));  // stops at the end
  EXPECT_FALSE(p.playing());
  p.play(2.0, range, frame);  // playing from the end starts over
  EXPECT_EQ(frame, 1);
  EXPECT_EQ(p.step(frame, -1, range), 1);  // clamped, and stepping pauses
  EXPECT_FALSE(p.playing());
  EXPECT_EQ(p.step(4, 3, range), 5);
}

}  // namespace
}  // namespace loom::editor
