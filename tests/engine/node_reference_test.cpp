// What the runner prints for people: `loom nodes TYPE` with ranges and
// choices, `--markdown` for one type, ranges as numbers in docs/nodes.md,
// `--target` outputs by name with list values, "did you mean" and plugin
// path warnings.
#include <cstdlib>
#include <fstream>

#include <gtest/gtest.h>

#include "loom/builtin_types.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

bool has(const std::string& text, const std::string& fragment) { return text.find(fragment) != std::string::npos; }

TEST(NodesCommand, OneTypeInPlainTextShowsRangesAndChoices) {
  std::string out;
  ASSERT_EQ(test::run_loom("nodes Posterize", &out), 0) << out;
  EXPECT_TRUE(has(out, "in  levels: Int = 4, range [2, 256]  values per channel")) << out;
  ASSERT_EQ(test::run_loom("nodes Math", &out), 0) << out;
  EXPECT_TRUE(has(out, "one of add | subtract | multiply")) << out;
  EXPECT_TRUE(has(out, "out result: Float")) << out;
}

TEST(NodesCommand, MarkdownOfOneTypeIsThatTypeOnly) {
  std::string out;
  ASSERT_EQ(test::run_loom("nodes Posterize --markdown", &out), 0) << out;
  EXPECT_EQ(out.rfind("### Posterize\n", 0), 0u) << out;
  EXPECT_FALSE(has(out, "# Node reference")) << out;
  EXPECT_EQ(out.find("### ", 1), std::string::npos) << out;  // no other type
  EXPECT_TRUE(has(out, "| `levels` | Int | `4` | values per channel [2, 256] |")) << out;
}

TEST(NodesCommand, ReferencePrintsRangesAsNumbers) {
  std::string out;
  ASSERT_EQ(test::run_loom("nodes --markdown", &out), 0);
  EXPECT_FALSE(has(out, ".000000")) << "ranges printed with %f";
  EXPECT_TRUE(has(out, "[2, 256]"));
  EXPECT_TRUE(has(out, "[1e-09, 1e+09]"));  // GridMesh size: not 0.000000
}

TEST(NodesCommand, UnknownTypeSuggestsANearOne) {
  std::string out;
  EXPECT_EQ(test::run_loom("nodes posterise", &out), 2);
  EXPECT_TRUE(has(out, "did you mean \"Posterize\"?")) << out;
}

TEST(RunCommand, UnknownTypeSuggestsOneFromAPluginNotLoaded) {
  const auto dir = test::temp_dir();
  std::ofstream(dir / "g.json") << R"({"loom": 1, "nodes": {"s": {"type": "saveimage"}}})";
  std::string out;
  EXPECT_EQ(test::run_loom("validate " + (dir / "g.json").string(), &out), 2) << out;
  EXPECT_TRUE(has(out, "did you mean \"SaveImage\"?")) << out;
  EXPECT_TRUE(has(out, "LOOM_PLUGIN_PATH")) << out;
}

TEST(RunCommand, TargetPrintsEveryOutputByNameWithListValues) {
  const auto dir = test::temp_dir();
  std::ofstream(dir / "g.json") << R"({"loom": 1, "nodes": {
    "g": {"type": "GridMesh", "inputs": {"resolution": [3, 3]}},
    "a": {"type": "ARAP", "inputs": {"mesh": {"from": "g.mesh"}, "iterations": 2, "tolerance": 0}}}})";
  std::string out;
  ASSERT_EQ(test::run_loom("run " + (dir / "g.json").string() + " --target a -q", &out), 0) << out;
  EXPECT_EQ(out.rfind("a.mesh = Mesh 16 vertices, 18 faces", 0), 0u) << out;
  EXPECT_TRUE(has(out, "\na.distortion = {")) << out;
  EXPECT_TRUE(has(out, "\na.energy = FloatList of 3: [")) << out;  // initial + 2 iterations
}

TEST(ListSummary, ShowsTheLengthAndTheFirstValues) {
  EXPECT_EQ(Value::make(std::vector<double>{0.5, 1, 2}).summary(), "FloatList of 3: [0.5, 1, 2]");
  EXPECT_EQ(Value::make(std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8}).summary(), "IntList of 8: [1, 2, 3, 4, 5, 6, ...]");
  EXPECT_EQ(Value::make(std::vector<std::string>{"a"}).summary(), "StringList of 1: [\"a\"]");
  EXPECT_EQ(Value::make(std::vector<int>{}).summary(), "IntList of 0: []");
}

TEST(PluginsCommand, WarnsAboutPathEntriesThatCannotHoldPlugins) {
  const auto dir = test::temp_dir();
  std::ofstream(dir / "libloom_mine.so") << "x";
  const std::string path = (dir / "missing").string() + ":" + (dir / "libloom_mine.so").string();
  ::setenv("LOOM_PLUGIN_PATH", path.c_str(), 1);
  std::string out;
  const int code = test::run_loom("plugins", &out);
  ::unsetenv("LOOM_PLUGIN_PATH");
  EXPECT_EQ(code, 0) << out;
  EXPECT_TRUE(has(out, "warning: plugin path: " + (dir / "missing").string() + " does not exist")) << out;
  EXPECT_TRUE(has(out, "libloom_mine.so is a file, not a folder")) << out;
}

}  // namespace
}  // namespace loom
