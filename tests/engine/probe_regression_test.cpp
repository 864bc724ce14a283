// The probe's reproducers (issue 15, item 3), each as a regression test of the
// real runner: a clear error and the documented exit code, never a crash, a
// hang or a silently wrong result.
#include <fstream>
#include <tuple>

#include <gtest/gtest.h>

#include "loom/graph.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

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
  EXPECT_EQ(parse_link("a.b.c")->output, "c");  // ids and names hold no '.': the member is after the last
  EXPECT_FALSE(parse_link("a."));
  EXPECT_FALSE(parse_link(".b"));
  EXPECT_FALSE(parse_link("ab"));
}

}  // namespace
}  // namespace loom

namespace loom {
namespace {

// Runs a graph document through the runner; returns the exit code.
int run_doc(const json& doc, std::string* out, const std::string& extra = "") {
  auto dir = test::temp_dir();
  std::ofstream(dir / "g.json") << doc.dump();
  return test::run_loom("run " + (dir / "g.json").string() + " --out " + (dir / "out").string() + " " + extra, out);
}

json link(const std::string& from) { return {{"from", from}}; }

TEST(LinkedValues, RangesAreCheckedOnLinkedValues) {
  struct Case {
    std::string source_type;
    json value;
    std::string type, input;
    json sink_from;
  };
  // Each: a constant linked into a declared-range input, and a sink that
  // consumes the node's result.
  const std::vector<Case> cases = {
      {"IntConstant", 0, "UVSphere", "rings", "n.mesh"},
      {"IntConstant", 1, "Posterize", "levels", "n.image"},
      {"FloatConstant", 0.0, "UVSphere", "radius", "n.mesh"},
      {"IntConstant", 409600, "HemisphereMesh", "rings", "n.mesh"},
      {"IntConstant", 7, "Switch", "index", "n.value"},
  };
  for (const Case& c : cases) {
    json inputs = {{c.input, link("c.value")}};
    if (c.type == "Posterize") inputs["image"] = link("board.image");
    json nodes = {{"c", {{"type", c.source_type}, {"inputs", {{"value", c.value}}}}},
                  {"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {8, 8}}}}}},
                  {"n", {{"type", c.type}, {"inputs", inputs}}},
                  {"p", {{"type", "Print"}, {"inputs", {{"value", link(c.sink_from)}}}}}};
    std::string out;
    EXPECT_EQ(run_doc({{"loom", 1}, {"nodes", nodes}}, &out), 1) << c.type << ": " << out;
    EXPECT_NE(out.find("input \"" + c.input + "\""), std::string::npos) << out;
    EXPECT_NE(out.find("out of range"), std::string::npos) << out;
  }
}

TEST(LinkedValues, InputsTheBodyDoesNotReadAreCheckedToo) {
  // WarpField reads idw_power and idw_affine only for method "idw": the
  // engine checks linked values before the body runs, read or not.
  for (const auto& [input, source, value] :
       {std::tuple<std::string, std::string, json>{"idw_power", "FloatConstant", 0.001},
        {"idw_affine", "StringConstant", "bogus"}}) {
    json nodes = {{"c", {{"type", source}, {"inputs", {{"value", value}}}}},
                  {"w", {{"type", "WarpField"}, {"inputs", {{"size", {8, 8}}, {input, link("c.value")}}}}},
                  {"p", {{"type", "Print"}, {"inputs", {{"value", link("w.displacement")}}}}}};
    std::string out;
    EXPECT_EQ(run_doc({{"loom", 1}, {"nodes", nodes}}, &out), 1) << input << ": " << out;
    EXPECT_NE(out.find("input \"" + input + "\""), std::string::npos) << out;
  }
}

TEST(LinkedValues, EnumChoicesAreCheckedOnLinkedValues) {
  json nodes = {{"s", {{"type", "StringConstant"}, {"inputs", {{"value", "bogus"}}}}},
                {"m", {{"type", "Math"}, {"inputs", {{"op", link("s.value")}}}}},
                {"p", {{"type", "Print"}, {"inputs", {{"value", link("m.result")}}}}}};
  std::string out;
  EXPECT_EQ(run_doc({{"loom", 1}, {"nodes", nodes}}, &out), 1) << out;
  EXPECT_NE(out.find("\"bogus\" is not one of the choices"), std::string::npos) << out;
}

TEST(LinkedValues, ParameterizeWeightsHaveTheirChoices) {
  std::string out;
  ASSERT_EQ(test::run_loom("nodes --json Parameterize", &out), 0) << out;
  const json j = json::parse(out.substr(out.find('{')));
  bool found = false;
  for (const json& in : j["Parameterize"]["inputs"])
    if (in["name"] == "weights") {
      found = true;
      EXPECT_GE(in["choices"].size(), 5u) << in.dump();
    }
  EXPECT_TRUE(found) << out.substr(0, 500);
}

json save_doc(const json& path) {
  return {{"loom", 1},
          {"nodes",
           {{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {8, 8}}}}}},
            {"name", {{"type", "StringConstant"}, {"inputs", {{"value", path}}}}},
            {"s", {{"type", "SaveImage"}, {"inputs", {{"image", link("board.image")}, {"path", link("name.value")}}}}}}}};
}

TEST(OutputPaths, LinkedPathsResolveUnderTheOutputFolder) {
  auto dir = test::temp_dir();
  std::ofstream(dir / "g.json") << save_doc("linked.png").dump();
  std::string out;
  ASSERT_EQ(test::run_loom("run " + (dir / "g.json").string() + " --out " + (dir / "out").string(), &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir / "out" / "linked.png"));
}

TEST(OutputPaths, EscapesNulBytesAndAbsolutePathsAreRefused) {
  auto dir = test::temp_dir();
  for (const std::string& bad : {std::string("evil.sh\0.png", 12), std::string("../../x.png"),
                                 std::string("a/../../x.png"), (dir / "abs.png").string(), std::string("x\n.png")}) {
    for (bool linked : {false, true}) {
      json doc = save_doc(bad);
      if (!linked) doc["nodes"]["s"]["inputs"]["path"] = bad;
      std::ofstream(dir / "g.json") << doc.dump();
      std::string out;
      const int rc = test::run_loom("run " + (dir / "g.json").string() + " --out " + (dir / "out").string(), &out);
      EXPECT_NE(rc, 0) << json(bad).dump() << " linked=" << linked << ": " << out;
      EXPECT_TRUE(out.find("output folder") != std::string::npos || out.find("control character") != std::string::npos)
          << out;
    }
  }
  EXPECT_FALSE(fs::exists(dir / "evil.sh"));
  EXPECT_FALSE(fs::exists(dir / "out" / "evil.sh"));
  EXPECT_FALSE(fs::exists(dir / "abs.png"));
  EXPECT_FALSE(fs::exists(dir.parent_path().parent_path() / "x.png"));
  // With the flag, an absolute path is written.
  json doc = save_doc((dir / "abs.png").string());
  std::ofstream(dir / "g.json") << doc.dump();
  std::string out;
  EXPECT_EQ(test::run_loom("run " + (dir / "g.json").string() + " --out " + (dir / "out").string() +
                               " --allow-outside-out", &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir / "abs.png"));
}

}  // namespace
}  // namespace loom
