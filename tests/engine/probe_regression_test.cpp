// The probe's reproducers (issue 15, item 3), each as a regression test of the
// real runner: a clear error and the documented exit code, never a crash, a
// hang or a silently wrong result.
#include <fstream>

#include <gtest/gtest.h>

#include "loom/graph.hpp"
#include "loom_test.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

fs::path write_graph(const fs::path& dir, const std::string& text, const std::string& name = "g.json") {
  std::ofstream(dir / name, std::ios::binary) << text;
  return dir / name;
}

int loom(const std::string& args, std::string* out) { return test::run_loom(args, out); }

TEST(ProbeRegression, ANumberBeyondDoubleIsAnInvalidGraph) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, R"({"loom":1,"nodes":{"a":{"type":"FloatConstant","inputs":{"value":1e400}}}})");
  std::string out;
  EXPECT_EQ(loom("validate " + g.string(), &out), 2) << out;
  EXPECT_NE(out.find("number overflow"), std::string::npos) << out;
  EXPECT_EQ(loom("run " + g.string() + " --out " + (dir / "o").string(), &out), 2) << out;
}

TEST(ProbeRegression, DeepNestingIsRefusedWhenParsed) {
  auto dir = test::temp_dir();
  std::string deep(70000, '[');
  deep += std::string(70000, ']');
  auto g = write_graph(dir, R"({"loom":1,"nodes":{"a":{"type":"FloatConstant","inputs":{"value":)" + deep + "}}}}");
  std::string out;
  EXPECT_EQ(loom("validate " + g.string(), &out), 2) << out;
  EXPECT_NE(out.find("nested deeper than 256"), std::string::npos) << out;
  EXPECT_EQ(loom("run " + g.string() + " --out " + (dir / "o").string() + " --set 'a.value=" +
                     std::string(5000, '[') + "'", &out), 2);
}

TEST(ProbeRegression, InvalidUtf8InSetIsAnInvalidGraph) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, R"({"loom":1,"nodes":{"board":{"type":"Checkerboard"},
    "s":{"type":"SaveImage","inputs":{"image":{"from":"board.image"},"path":"x.png"}}}})");
  std::string out;
  EXPECT_EQ(loom("run " + g.string() + " --out " + (dir / "o").string() + " --set \"board.cells=$(printf '\\377')\"", &out), 2)
      << out;
  EXPECT_NE(out.find("UTF-8"), std::string::npos) << out;
  EXPECT_EQ(loom("run " + g.string() + " --out " + (dir / "o").string() + " --set 'board.cells=1e400'", &out), 2)
      << out;
}

TEST(ProbeRegression, AHugeCycleIsReportedBriefly) {
  auto dir = test::temp_dir();
  const int n = 20000;
  json nodes = json::object();
  for (int i = 0; i < n; ++i)
    nodes["n" + std::to_string(i)] = {
        {"type", "Math"},
        {"inputs",
         {{"a", {{"from", "n" + std::to_string((i + 1) % n) + ".result"}}},
          {"b", {{"from", "n" + std::to_string((i * 7 + 3) % n) + ".result"}}}}}};
  auto g = write_graph(dir, json{{"loom", 1}, {"nodes", nodes}}.dump());
  std::string out;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(loom("validate " + g.string(), &out), 2);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  EXPECT_LT(out.size(), 20000u);
  EXPECT_NE(out.find("cycle of 20000 nodes"), std::string::npos) << out.substr(0, 2000);
  EXPECT_NE(out.find("more links close cycles"), std::string::npos);
}

TEST(ProbeRegression, OneLinkParser) {
  EXPECT_EQ(parse_link("a.b")->node, "a");
  EXPECT_EQ(parse_link("a.b.c")->output, "b.c");
  EXPECT_FALSE(parse_link("a."));
  EXPECT_FALSE(parse_link(".b"));
  EXPECT_FALSE(parse_link("ab"));
}

}  // namespace
}  // namespace loom
