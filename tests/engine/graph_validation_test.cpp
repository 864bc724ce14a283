// Every validation error names the file, the JSON pointer and what was expected.
#include <fstream>

#include <gtest/gtest.h>

#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

std::vector<GraphIssue> issues_of(const json& doc) {
  testing::Engine engine;
  try {
    engine.load(doc, "/tmp/g.json");
  } catch (const GraphError& e) {
    EXPECT_EQ(e.file(), "/tmp/g.json");
    return e.issues();
  }
  ADD_FAILURE() << "graph accepted: " << doc.dump();
  return {};
}

void expect_issue(const json& doc, const std::string& pointer, const std::string& fragment) {
  auto issues = issues_of(doc);
  ASSERT_EQ(issues.size(), 1u) << doc.dump();
  EXPECT_EQ(issues[0].pointer, pointer);
  EXPECT_NE(issues[0].message.find(fragment), std::string::npos) << issues[0].message;
}

json graph(json nodes) { return {{"loom", 1}, {"nodes", std::move(nodes)}}; }

TEST(GraphValidation, UnknownTypeNamesThePluginsSearched) {
  expect_issue(graph({{"a", {{"type", "Nope"}}}}), "/nodes/a/type", "searched plugins:");
}

TEST(GraphValidation, UnknownInputListsTheKnownOnes) {
  expect_issue(graph({{"a", {{"type", "Math"}, {"inputs", {{"c", 1}}}}}}), "/nodes/a/inputs/c",
               "its inputs: a, b, op");
}

TEST(GraphValidation, TypeMismatchOfALink) {
  expect_issue(graph({{"s", {{"type", "StringConstant"}, {"inputs", {{"value", "x"}}}}},
                      {"m", {{"type", "Math"}, {"inputs", {{"a", {{"from", "s.value"}}}}}}}}),
               "/nodes/m/inputs/a/from", "type mismatch: s.value is String but input \"a\" expects Float");
}

TEST(GraphValidation, TypeMismatchOfALiteral) {
  expect_issue(graph({{"m", {{"type", "Math"}, {"inputs", {{"a", "two"}}}}}}), "/nodes/m/inputs/a",
               "expected a number, got \"two\" (a string)");
}

TEST(GraphValidation, Cycle) {
  auto issues = issues_of(graph({{"a", {{"type", "Math"}, {"inputs", {{"a", {{"from", "b.result"}}}}}}},
                                 {"b", {{"type", "Math"}, {"inputs", {{"a", {{"from", "a.result"}}}}}}}}));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_NE(issues[0].message.find("cycle of 2 nodes: "), std::string::npos) << issues[0].message;
}

TEST(GraphValidation, MissingRequiredInput) {
  expect_issue(graph({{"p", {{"type", "Print"}}}}), "/nodes/p/inputs", "missing required input \"value\"");
}

TEST(GraphValidation, BadEnumValue) {
  expect_issue(graph({{"m", {{"type", "Math"}, {"inputs", {{"op", "modulo"}}}}}}), "/nodes/m/inputs/op",
               "\"modulo\" is not one of the choices");
}

TEST(GraphValidation, OutOfRangeValue) {
  expect_issue(graph({{"s", {{"type", "Switch"}, {"inputs", {{"index", 7}}}}}}), "/nodes/s/inputs/index",
               "out of range: expected between 0 and 3");
}

TEST(GraphValidation, LinkToUnknownNodeOrOutput) {
  expect_issue(graph({{"m", {{"type", "Math"}, {"inputs", {{"a", {{"from", "zz.result"}}}}}}}}),
               "/nodes/m/inputs/a/from", "unknown node \"zz\"");
  expect_issue(graph({{"c", {{"type", "FloatConstant"}}},
                      {"m", {{"type", "Math"}, {"inputs", {{"a", {{"from", "c.nope"}}}}}}}}),
               "/nodes/m/inputs/a/from", "has no output \"nope\"");
}

TEST(GraphValidation, StructureErrors) {
  EXPECT_THROW(parse_graph(json{{"nodes", json::object()}}, "x.json"), GraphError);       // no version
  EXPECT_THROW(parse_graph(json{{"loom", 3}, {"nodes", json::object()}}, "x.json"), GraphError);
  EXPECT_THROW(parse_graph(json{{"loom", 1}, {"nodes", json::array()}}, "x.json"), GraphError);
  try {
    parse_graph(json{{"loom", 1}, {"nodes", {{"a", {{"type", "Math"}, {"inputs", {{"a", {{"from", "bad"}}}}}}}}}},
                "x.json");
    FAIL();
  } catch (const GraphError& e) {
    EXPECT_EQ(e.issues().at(0).pointer, "/nodes/a/inputs/a/from");
  }
}

TEST(GraphValidation, PointerEscapesSlashAndTilde) {
  expect_issue(graph({{"a/b~c", {{"type", "Nope"}}}}), "/nodes/a~1b~0c/type", "unknown node type");
}

TEST(GraphValidation, ReportsEveryIssueAtOnce) {
  auto issues = issues_of(graph({{"a", {{"type", "Math"}, {"inputs", {{"a", "x"}, {"op", "y"}}}}},
                                 {"b", {{"type", "Nope"}}}}));
  EXPECT_EQ(issues.size(), 3u);
}

TEST(GraphValidation, SyntaxErrorNamesTheFile) {
  auto dir = test::temp_dir();
  std::ofstream(dir / "broken.json") << "{\"loom\": 1, \"nodes\": {";
  try {
    load_graph_file(dir / "broken.json");
    FAIL();
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.json: not valid JSON"), std::string::npos) << e.what();
  }
}

TEST(GraphValidation, SetOverridesAndRoundTrips) {
  Graph g = parse_graph(graph({{"m", {{"type", "Math"}, {"inputs", {{"a", 1}}}}}}), "x.json");
  set_input(g, "m.a=2.5");
  set_input(g, "m.op=multiply");  // not JSON: taken as a string
  json back = graph_to_json(g);
  EXPECT_EQ(back["nodes"]["m"]["inputs"]["a"], 2.5);
  EXPECT_EQ(back["nodes"]["m"]["inputs"]["op"], "multiply");
  EXPECT_THROW(set_input(g, "zz.a=1"), GraphError);
}

}  // namespace
}  // namespace loom
