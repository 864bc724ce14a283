// loom::testing, the helper plugin authors test with: statuses of failed and
// skipped nodes, errors that name the node, sinks writing into the folder
// given, graph errors before anything runs, and the plugin path it builds.
#include <fstream>

#include <gtest/gtest.h>

#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

using testing::GraphBuilder;

TEST(LoomTesting, FindsLoomsOwnPluginsBesideItself) {
  testing::Engine engine;
  EXPECT_EQ(testing::installed_plugin_dir(), std::filesystem::path(LOOM_PLUGIN_DIR).lexically_normal());
  EXPECT_EQ(engine.plugin_path().front(), testing::installed_plugin_dir());
  GraphBuilder g;
  g.node("m", "Math").set("a", 2).set("b", 3).set("op", "multiply");
  EXPECT_EQ(engine.output<double>(g, "m.result"), 6.0);
  EXPECT_EQ(engine.loaded_plugins(), std::vector<std::string>{"util"});
}

TEST(LoomTesting, AFailedNodeAndWhatItSkips) {
  testing::Engine engine({LOOM_TEST_PLUGIN_DIR});
  GraphBuilder g;
  g.node("bad", "Fail");
  g.node("after", "Math").link("a", "bad.value");
  testing::Run run = engine.run(g, {"after.result"});
  EXPECT_FALSE(run.ok());
  EXPECT_EQ(run.status("bad"), NodeStatus::failed);
  EXPECT_EQ(run.error("bad"), "failing on purpose");
  EXPECT_EQ(run.status("after"), NodeStatus::skipped);
  EXPECT_NE(run.errors().find("bad failed: failing on purpose"), std::string::npos) << run.errors();
  try {
    (void)run.output<double>("after.result");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("node \"after\" skipped"), std::string::npos) << e.what();
  }
  EXPECT_THROW(engine.output<double>(g, "after.result"), Error);
  EXPECT_THROW(run.status("nobody"), Error);
}

TEST(LoomTesting, OnlyTargetsHaveOutputs) {
  testing::Engine engine;
  GraphBuilder g;
  g.node("a", "FloatConstant").set("value", 1.5);
  testing::Run run = engine.run(g, {"a"});
  EXPECT_EQ(run.output<double>("a"), 1.5);  // the node's only output
  try {
    (void)run.value("b.value");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a target of this run"), std::string::npos) << e.what();
  }
}

TEST(LoomTesting, SinksWriteIntoTheFolderGiven) {
  testing::Engine engine({LOOM_TEST_PLUGIN_DIR});
  const auto out = test::temp_dir();
  GraphBuilder g;
  g.node("w", "WriteText").set("value", 4).set("path", "sub/v.txt");
  ASSERT_TRUE(engine.run(g, {}, out).ok());
  std::ifstream in(out / "sub" / "v.txt");
  double v = 0;
  in >> v;
  EXPECT_EQ(v, 4.0);
}

TEST(LoomTesting, TheDefaultOutputFolderGoesWithTheEngine) {
  std::filesystem::path dir;
  {
    testing::Engine engine({LOOM_TEST_PLUGIN_DIR});
    GraphBuilder g;
    g.node("w", "WriteText").set("value", 2).set("path", "v.txt");
    ASSERT_TRUE(engine.run(g).ok());
    dir = engine.output_dir();
    EXPECT_TRUE(std::filesystem::exists(dir / "v.txt"));
  }
  EXPECT_FALSE(std::filesystem::exists(dir));
}

TEST(LoomTesting, GraphErrorsComeBeforeAnythingRuns) {
  testing::Engine engine;
  GraphBuilder g;
  g.node("m", "math");
  try {
    engine.run(g);
    FAIL() << "accepted";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean \"Math\"?"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace loom
