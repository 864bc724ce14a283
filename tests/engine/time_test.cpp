// Time and simulation state through the real engine: frame-independent nodes
// run once, state feedback equals a hand-written loop of steps, scrubbing
// reuses states, the invalidation rules, the state copy count and budget.
#include <mutex>
#include <set>

#include <gtest/gtest.h>

#include "loom/disk_cache.hpp"
#include "loom/frame_pattern.hpp"
#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

struct RunLog : Observer {
  std::mutex mutex;
  std::multiset<std::string> started;
  std::vector<int> frames;
  void node_started(const std::string& id, const std::string&) override {
    std::lock_guard lock(mutex);
    started.insert(id);
  }
  void frame_started(int frame, int, int) override {
    std::lock_guard lock(mutex);
    frames.push_back(frame);
  }
  int count(const std::string& id) {
    std::lock_guard lock(mutex);
    return static_cast<int>(started.count(id));
  }
  void reset() {
    std::lock_guard lock(mutex);
    started.clear();
    frames.clear();
  }
};

json graph(json nodes, int start = 1, int end = 1, double fps = 24) {
  return {{"loom", 1}, {"time", {{"start", start}, {"end", end}, {"fps", fps}}}, {"nodes", std::move(nodes)}};
}
json from(const std::string& link) { return {{"from", link}}; }

EvalResult at_frames(testing::Engine& e, const Graph& g, int first, int last, std::vector<std::string> targets,
                     RunLog* log, std::size_t state_budget = std::size_t(1) << 30) {
  EvalOptions o;
  for (const auto& t : targets) o.targets.push_back(parse_target(t));
  o.observer = log;
  o.frames = FrameRange{first, last};
  o.output_dir = test::temp_dir();
  o.state_memory_budget = state_budget;
  return e.session().evaluate(g, o);
}

double number(const EvalResult& r, const std::string& target) { return r.outputs.at(target).at(0).as<double>(); }

TEST(Time, AFrameIndependentNodeRunsOnceAcross240Frames) {
  testing::Engine e;
  // The static part is a 30 ms Sleep; the time-dependent part one FrameNumber.
  Graph g = e.load(
      graph({{"expensive", {{"type", "Sleep"}, {"inputs", {{"value", 1000}, {"ms", 30}}}}},
             {"frame", {{"type", "FrameNumber"}}},
             {"sum", {{"type", "Math"}, {"inputs", {{"a", from("expensive.value")}, {"b", from("frame.value")}}}}}},
            1, 240));
  RunLog log;
  EvalResult r = at_frames(e, g, 1, 240, {"sum.result"}, &log);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.frames, 240);
  EXPECT_EQ(log.count("expensive"), 1);
  EXPECT_EQ(log.count("frame"), 240);
  EXPECT_EQ(log.count("sum"), 240);
  EXPECT_EQ(r.nodes.at("expensive").runs, 1);
  EXPECT_EQ(r.nodes.at("expensive").memory_hits, 239);  // read from memory by every later frame
  EXPECT_DOUBLE_EQ(number(r, "sum.result"), 1240.0);
  EXPECT_EQ(log.frames.size(), 240u);
  EXPECT_EQ(log.frames.front(), 1);
  EXPECT_EQ(log.frames.back(), 240);
}

TEST(Time, ANodeThatDoesNotReadTimeIsNotEvaluatedPerFrame) {
  testing::Engine e;
  Graph g = e.load(graph({{"a", {{"type", "Math"}, {"inputs", {{"a", 1}, {"b", 2}}}}}}, 1, 10));
  RunLog log;
  EvalResult r = at_frames(e, g, 1, 10, {"a.result"}, &log);
  EXPECT_EQ(log.count("a"), 1);
  EXPECT_EQ(r.nodes.at("a").memory_hits, 9);
  EXPECT_DOUBLE_EQ(number(r, "a.result"), 3.0);
}

// x(f) by hand: the same operations in the same order as Integrate.
double integrate_by_hand(double x0, double v, int substeps, int start, int frame, double fps) {
  double x = x0;
  for (int f = start + 1; f <= frame; ++f)
    for (int i = 0; i < substeps; ++i) x += v * (1.0 / fps / substeps);
  return x;
}

TEST(Time, StateFeedbackEqualsAHandWrittenLoopOfSteps) {
  testing::Engine e;
  Graph g = e.load(
      graph({{"sim", {{"type", "Integrate"}, {"inputs", {{"x", 2.5}, {"v", -3.0}, {"substeps", 3}}}}}}, 5, 200, 30));
  RunLog log;
  EvalResult r = at_frames(e, g, 5, 200, {"sim.x"}, &log);
  ASSERT_TRUE(r.ok()) << r.nodes.at("sim").error;
  EXPECT_EQ(number(r, "sim.x"), integrate_by_hand(2.5, -3.0, 3, 5, 200, 30));
  EXPECT_EQ(log.count("sim"), 196);  // one step per frame
  // The start frame gives the initial state unchanged (step 0).
  r = at_frames(e, g, 5, 5, {"sim.x"}, &log);
  EXPECT_EQ(number(r, "sim.x"), 2.5);
}

TEST(Time, AskingForALateFrameStepsEveryEarlierFrameOnceAndScrubbingBackReusesThem) {
  testing::Engine e;
  Graph g = e.load(graph({{"sim", {{"type", "Integrate"}, {"inputs", {{"x", 0.0}, {"v", 1.5}}}}},
                          {"out", {{"type", "Math"}, {"inputs", {{"a", from("sim.x")}, {"b", 100}}}}}},
                         1, 240));
  RunLog log;
  EvalResult r = at_frames(e, g, 120, 120, {"out.result"}, &log);
  ASSERT_TRUE(r.ok()) << r.nodes.at("sim").error;
  EXPECT_EQ(log.count("sim"), 120);  // frames 1..120, each once
  EXPECT_EQ(r.nodes.at("sim").runs, 120);
  EXPECT_DOUBLE_EQ(number(r, "out.result"), 100 + integrate_by_hand(0, 1.5, 1, 1, 120, 24));
  log.reset();
  r = at_frames(e, g, 60, 60, {"out.result"}, &log);
  EXPECT_EQ(log.count("sim"), 0);
  EXPECT_EQ(number(r, "out.result"), 100 + integrate_by_hand(0, 1.5, 1, 1, 60, 24));
  r = at_frames(e, g, 120, 120, {"sim.x"}, &log);
  EXPECT_EQ(log.count("sim"), 0);
  EXPECT_EQ(r.nodes.at("sim").status, NodeStatus::cached);
  // Frame 130 steps on from 120, not from the start.
  r = at_frames(e, g, 130, 130, {"sim.x"}, &log);
  EXPECT_EQ(log.count("sim"), 10);
  EXPECT_EQ(number(r, "sim.x"), integrate_by_hand(0, 1.5, 1, 1, 130, 24));
}

TEST(Time, ASimulationParameterInvalidatesItsFramesADownstreamSettingDoesNot) {
  testing::Engine e;
  json doc = graph({{"sim", {{"type", "Integrate"}, {"inputs", {{"x", 0.0}, {"v", 1.0}}}}},
                    {"out", {{"type", "Math"}, {"inputs", {{"a", from("sim.x")}, {"b", 1}}}}}},
                   1, 50);
  Graph g = e.load(doc);
  RunLog log;
  at_frames(e, g, 1, 50, {"out.result"}, &log);
  EXPECT_EQ(log.count("sim"), 50);
  log.reset();
  set_input(g, "out.b=7");  // downstream only: no re-simulation
  EvalResult r = at_frames(e, g, 1, 50, {"out.result"}, &log);
  EXPECT_EQ(log.count("sim"), 0);
  EXPECT_EQ(log.count("out"), 50);
  EXPECT_DOUBLE_EQ(number(r, "out.result"), 7 + integrate_by_hand(0, 1, 1, 1, 50, 24));
  set_input(g, "sim.v=2");  // a parameter: every frame again
  r = at_frames(e, g, 50, 50, {"out.result"}, &log);
  EXPECT_EQ(log.count("sim"), 50);
  EXPECT_DOUBLE_EQ(number(r, "out.result"), 7 + integrate_by_hand(0, 2, 1, 1, 50, 24));
  log.reset();
  set_input(g, "sim.x=1");  // the initial state too
  at_frames(e, g, 10, 10, {"out.result"}, &log);
  EXPECT_EQ(log.count("sim"), 10);
}

TEST(Time, ATimeDependentParameterIsReadAtEachSteppedFrame) {
  testing::Engine e;
  // v(f) = f / 10: x(f) = sum over g = 2..f of v(g) / fps.
  Graph g = e.load(graph({{"v", {{"type", "FrameNumber"}, {"inputs", {{"scale", 0.1}}}}},
                          {"sim", {{"type", "Integrate"}, {"inputs", {{"x", 0.0}, {"v", from("v.value")}}}}}},
                         1, 40, 10));
  RunLog log;
  EvalResult r = at_frames(e, g, 40, 40, {"sim.x"}, &log);
  ASSERT_TRUE(r.ok()) << r.nodes.at("sim").error;
  double x = 0;
  for (int f = 2; f <= 40; ++f) x += (f * 0.1) * (1.0 / 10);
  EXPECT_DOUBLE_EQ(number(r, "sim.x"), x);
  EXPECT_EQ(log.count("v"), 40);  // once per frame (frame 1 steps by 0 and ignores it)
}

TEST(Time, AStepCopiesAMillionParticleStateOncePerFrameAndTheEngineNever) {
  testing::Engine e;
  Graph g = e.load(
      graph({{"init", {{"type", "MakeParticles"}, {"inputs", {{"count", 1000000}}}}},
             {"sim", {{"type", "MoveParticles"}, {"inputs", {{"particles", from("init.particles")}, {"v", 24.0}}}}},
             {"sum", {{"type", "ParticleSum"}, {"inputs", {{"particles", from("sim.particles")}}}}},
             {"copies", {{"type", "StateCopies"}}}},
            1, 10));
  RunLog log;
  const int before = at_frames(e, g, 1, 1, {"copies.value"}, &log).outputs.at("copies.value")[0].as<int>();
  EvalResult r = at_frames(e, g, 1, 10, {"sum.value"}, &log);
  ASSERT_TRUE(r.ok()) << r.nodes.at("sim").error;
  // Each particle moved by 24 * (1/24) per frame past the first: 9 in all.
  EXPECT_DOUBLE_EQ(number(r, "sum.value"), 1e6 * (1e6 - 1) / 2 + 9e6);
  const int after = at_frames(e, g, 1, 1, {"copies.value"}, &log).outputs.at("copies.value")[0].as<int>();
  EXPECT_EQ(after - before, 10);
}

TEST(Time, StatesBeyondTheMemoryBudgetAreDroppedButSteppingOnNeverRestarts) {
  testing::Engine e;
  Graph g = e.load(graph({{"init", {{"type", "MakeParticles"}, {"inputs", {{"count", 1000}}}}},
                          {"sim", {{"type", "MoveParticles"}, {"inputs", {{"particles", from("init.particles")}}}}},
                          {"sum", {{"type", "ParticleSum"}, {"inputs", {{"particles", from("sim.particles")}}}}}},
                         1, 30));
  RunLog log;
  const std::size_t five_states = 5 * 1000 * sizeof(double);
  at_frames(e, g, 1, 30, {"sum.value"}, &log, five_states);
  EXPECT_EQ(log.count("sim"), 30);  // linear, though most states were dropped on the way
  log.reset();
  at_frames(e, g, 28, 30, {"sum.value"}, &log, five_states);  // the newest states are kept
  EXPECT_EQ(log.count("sim"), 0);
  log.reset();
  EvalResult r = at_frames(e, g, 10, 10, {"sum.value"}, &log, five_states);  // dropped: stepped again
  EXPECT_EQ(log.count("sim"), 10);
  EXPECT_DOUBLE_EQ(number(r, "sum.value"), 999.0 * 1000 / 2 + 1000 * 9 / 24.0);
}

TEST(Time, FramesBeforeTheStartOrReversedAreRefused) {
  testing::Engine e;
  Graph g = e.load(graph({{"a", {{"type", "FrameNumber"}}}}, 10, 20));
  RunLog log;
  EXPECT_THROW(at_frames(e, g, 5, 12, {"a.value"}, &log), Error);
  EXPECT_THROW(at_frames(e, g, 15, 12, {"a.value"}, &log), Error);
  EvalResult r = at_frames(e, g, 12, 12, {"a.value"}, &log);
  EXPECT_DOUBLE_EQ(number(r, "a.value"), 12.0);
}

TEST(Time, FramePatternsExpandInOutputPaths) {
  EXPECT_EQ(expand_frame_pattern("f/cloth_{frame:04}.png", 7), "f/cloth_0007.png");
  EXPECT_EQ(expand_frame_pattern("f/cloth_{frame:4}.png", 12345), "f/cloth_12345.png");
  EXPECT_EQ(expand_frame_pattern("{frame}_{frame:2}", 3), "3_03");
  EXPECT_EQ(expand_frame_pattern("x{frame:03}", -4), "x-004");
  EXPECT_EQ(expand_frame_pattern("{frames}/{frame:}/{frame:x}/{other}", 5), "{frames}/{frame:}/{frame:x}/{other}");
  EXPECT_TRUE(has_frame_pattern("a_{frame}.png"));
  EXPECT_FALSE(has_frame_pattern("a_{fram}.png"));
}

TEST(Time, TheGraphTimeFieldIsValidatedAndSetByDashDashSet) {
  auto issues = [](const json& time) {
    try {
      parse_graph({{"loom", 1}, {"time", time}, {"nodes", json::object()}}, "t.json");
    } catch (const GraphError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(issues({{"start", 1}, {"end", 48}, {"fps", 24}}), "");
  EXPECT_NE(issues({{"start", 10}, {"end", 5}}).find("/time/end"), std::string::npos);
  EXPECT_NE(issues({{"fps", 0}}).find("/time/fps"), std::string::npos);
  EXPECT_NE(issues({{"start", 1.5}}).find("/time/start"), std::string::npos);
  EXPECT_NE(issues({{"stop", 3}}).find("/time/stop"), std::string::npos);
  EXPECT_NE(issues(24).find("/time"), std::string::npos);

  Graph g = parse_graph({{"loom", 1}, {"nodes", json::object()}}, "t.json");
  EXPECT_FALSE(g.time);
  set_input(g, "time.end=48");
  ASSERT_TRUE(g.time);
  EXPECT_EQ(g.time->start, 1);
  EXPECT_EQ(g.time->end, 48);
  set_input(g, "time.fps=30");
  EXPECT_EQ(g.time->fps, 30);
  EXPECT_THROW(set_input(g, "time.end=-5"), GraphError);
  EXPECT_EQ(graph_to_json(g)["time"], (json{{"start", 1}, {"end", 48}, {"fps", 30.0}}));
}

std::vector<int> span(int first, int last) {
  std::vector<int> v;
  for (int f = first; f <= last; ++f) v.push_back(f);
  return v;
}

// What a time slider marks: the frames whose result the session keeps.
TEST(Time, CachedFramesAreTheSimulationFramesStepped) {
  testing::Engine e;
  json nodes = {{"sim", {{"type", "Integrate"}, {"inputs", {{"v", 2.0}}}}},
                {"after", {{"type", "Math"}, {"inputs", {{"a", from("sim.x")}, {"b", 1}}}}},
                {"still", {{"type", "Math"}, {"inputs", {{"a", 1}, {"b", 2}}}}}};
  Graph g = e.load(graph(nodes, 1, 10));
  EXPECT_TRUE(e.session().cached_frames(g, "sim", {1, 10}).empty());
  EXPECT_TRUE(e.session().cached_frames(g, "still", {1, 10}).empty());
  ASSERT_TRUE(at_frames(e, g, 5, 5, {"sim", "still"}, nullptr).ok());  // steps 1..5 to get there
  EXPECT_EQ(e.session().cached_frames(g, "sim", {1, 10}), span(1, 5));
  EXPECT_EQ(e.session().cached_frames(g, "sim", {3, 4}), span(3, 4));
  // A node that does not read time has one result for every frame.
  EXPECT_EQ(e.session().cached_frames(g, "still", {1, 10}), span(1, 10));
  // Scrubbing on steps from the latest state: 6..8 join.
  ASSERT_TRUE(at_frames(e, g, 8, 8, {"sim"}, nullptr).ok());
  EXPECT_EQ(e.session().cached_frames(g, "sim", {1, 10}), span(1, 8));

  // A downstream setting keeps the simulation's frames...
  json downstream = nodes;
  downstream["after"]["inputs"]["b"] = 5;
  EXPECT_EQ(e.session().cached_frames(e.load(graph(downstream, 1, 10)), "sim", {1, 10}), span(1, 8));
  // ...a parameter of the simulation drops them all, until stepped again.
  json edited = nodes;
  edited["sim"]["inputs"]["v"] = 3.0;
  Graph g2 = e.load(graph(edited, 1, 10));
  EXPECT_TRUE(e.session().cached_frames(g2, "sim", {1, 10}).empty());
  ASSERT_TRUE(at_frames(e, g2, 2, 2, {"sim"}, nullptr).ok());
  EXPECT_EQ(e.session().cached_frames(g2, "sim", {1, 10}), span(1, 2));

  EXPECT_THROW(e.session().cached_frames(g, "nope", {1, 10}), Error);
}

TEST(Time, CachedFramesIncludeTheDiskCacheAndNeverASink) {
  DiskCache::Options o;
  o.dir = test::temp_dir() / "frames-cache";
  o.min_seconds = 0;
  DiskCache disk(o);
  json nodes = {{"sim", {{"type", "Integrate"}, {"inputs", {{"ms", 60}}}}},
                {"print", {{"type", "Print"}, {"inputs", {{"value", from("sim.x")}}}}}};
  {
    testing::Engine e;
    Graph g = e.load(graph(nodes, 1, 6));
    EvalOptions opt;
    opt.targets = {parse_target("sim")};
    opt.frames = FrameRange{1, 3};
    opt.disk_cache = &disk;
    ASSERT_TRUE(e.session().evaluate(g, opt).ok());
    EXPECT_TRUE(e.session().cached_frames(g, "print", {1, 6}, opt).empty());
  }
  testing::Engine fresh;  // nothing in memory: what the disk keeps
  Graph g = fresh.load(graph(nodes, 1, 6));
  EXPECT_TRUE(fresh.session().cached_frames(g, "sim", {1, 6}).empty());
  EvalOptions with_disk;
  with_disk.disk_cache = &disk;
  EXPECT_EQ(fresh.session().cached_frames(g, "sim", {1, 6}, with_disk), span(1, 3));
}

TEST(Time, TheGraphUiFieldIsKeptAndIgnored) {
  Graph g = parse_graph({{"loom", 1}, {"ui", {{"frame", 12}}}, {"nodes", json::object()}}, "t.json");
  EXPECT_EQ(g.ui, (json{{"frame", 12}}));
  EXPECT_EQ(graph_to_json(g)["ui"], (json{{"frame", 12}}));
}

}  // namespace
}  // namespace loom
