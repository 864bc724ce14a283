// The rules that sit under every evaluation: one binding rule for literal and
// linked values, one parser of "ID.MEMBER", declarations checked once at
// registration, bounded lazy nesting and bounded frame numbers.
#include <climits>
#include <fstream>

#include <gtest/gtest.h>

#include "loom/input_declaration.hpp"
#include "loom/search_path.hpp"
#include "loom/testing.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

json graph(json nodes) { return {{"loom", 1}, {"nodes", std::move(nodes)}}; }
json from(const std::string& link) { return {{"from", link}}; }

EvalResult evaluate(testing::Engine& e, const Graph& g, const std::vector<std::string>& targets, int threads = 0) {
  EvalOptions o;
  for (const auto& t : targets) o.targets.push_back(parse_target(t));
  o.threads = threads;
  o.output_dir = test::temp_dir();
  return e.session().evaluate(g, o);
}

// What follows the input's name in a message: the part the rule writes.
std::string after_input_name(const std::string& message) {
  const auto p = message.find("\": ");
  return p == std::string::npos ? message : message.substr(p + 3);
}

TEST(Binding, ALiteralAndALinkedValueAreRefusedInTheSameWords) {
  testing::Engine e;
  std::string literal_message;
  try {
    e.load(graph({{"s", {{"type", "Switch"}, {"inputs", {{"index", 5}}}}}}));
  } catch (const GraphError& error) {
    ASSERT_EQ(error.issues().size(), 1u);
    EXPECT_EQ(error.issues()[0].pointer, "/nodes/s/inputs/index");
    literal_message = error.issues()[0].message;
  }
  EXPECT_EQ(literal_message, "value 5 is out of range: expected between 0 and 3");

  Graph g = e.load(graph({{"five", {{"type", "IntConstant"}, {"inputs", {{"value", 5}}}}},
                          {"s", {{"type", "Switch"}, {"inputs", {{"index", from("five.value")}}}}}}));
  EvalResult r = evaluate(e, g, {"s.value"});
  ASSERT_EQ(r.nodes.at("s").status, NodeStatus::failed);
  EXPECT_EQ(r.nodes.at("s").error.rfind("input \"index\": ", 0), 0u) << r.nodes.at("s").error;
  EXPECT_EQ(after_input_name(r.nodes.at("s").error), literal_message);
}

TEST(Binding, ALiteralAndALinkedOutputPathAreConfinedAlike) {
  testing::Engine e;
  const json write = {{"type", "WriteText"}, {"inputs", {{"value", 1.0}, {"path", "../outside.txt"}}}};
  std::string literal;  // a literal is bound when the plan is built: the evaluation refuses to start
  try {
    evaluate(e, e.load(graph({{"w", write}})), {});
    ADD_FAILURE() << "a literal path out of --out was accepted";
  } catch (const Error& error) {
    literal = error.what();
  }
  EXPECT_EQ(literal.rfind("node \"w\": input \"path\": ", 0), 0u) << literal;

  json linked = write;
  linked["inputs"]["path"] = from("p.value");
  EvalResult via_link = evaluate(
      e, e.load(graph({{"p", {{"type", "StringConstant"}, {"inputs", {{"value", "../outside.txt"}}}}}, {"w", linked}})),
      {});
  ASSERT_EQ(via_link.nodes.at("w").status, NodeStatus::failed);
  EXPECT_NE(literal.find("leaves the output folder"), std::string::npos) << literal;
  EXPECT_EQ(after_input_name(via_link.nodes.at("w").error), after_input_name(literal.substr(literal.find("input"))));
}

TEST(Binding, OneParserOfIdDotMember) {
  auto link = parse_link("warp.image");
  ASSERT_TRUE(link);
  EXPECT_EQ(link->node, "warp");
  EXPECT_EQ(link->output, "image");
  link = parse_link("look.render.image");  // a path of nodes: the member is after the last '.'
  ASSERT_TRUE(link);
  EXPECT_EQ(link->node, "look.render");
  EXPECT_EQ(link->output, "image");
  for (const char* bad : {"warp", ".image", "warp.", ""}) EXPECT_FALSE(parse_link(bad)) << bad;
  const Target t = parse_target("warp");
  EXPECT_EQ(t.node, "warp");
  EXPECT_EQ(t.output, "");
}

TEST(Binding, OneWriterOfIdDotMember) {
  for (const char* text : {"warp.image", "look.render.image", "a.b.c.d"}) {
    const auto link = parse_link(text);
    ASSERT_TRUE(link) << text;
    EXPECT_EQ(link_text(*link), text);
  }
  EXPECT_EQ(link_text("look.render", "width"), "look.render.width");
}

// Every input of every node Loom ships, written as a declaration and read
// back, is the same input: the reader and the writer speak one vocabulary.
TEST(Binding, EveryShippedInputSurvivesItsDeclaration) {
  testing::Engine engine;
  engine.load_all_plugins();
  int inputs = 0;
  for (const NodeType* type : engine.registry().all())
    for (const InputSpec& in : type->spec.inputs) {
      if (in.lazy || in.role != InputRole::value) continue;  // not part of the vocabulary
      const json written = input_spec_to_json(in);
      const InputSpec read = input_spec_from_json(in.name, written);
      const std::string where = type->spec.name + "." + in.name + " " + written.dump();
      EXPECT_EQ(read.type, in.type) << where;
      EXPECT_EQ(read.default_value, in.default_value) << where;
      EXPECT_EQ(read.min, in.min) << where;
      EXPECT_EQ(read.max, in.max) << where;
      EXPECT_EQ(read.choices, in.choices) << where;
      EXPECT_EQ(read.optional, in.optional) << where;
      EXPECT_EQ(read.description, in.description) << where;
      ++inputs;
    }
  EXPECT_GT(inputs, 200);
}

TEST(Binding, ADeclarationIsReadStrictlyOrLeniently) {
  const json bad = {{"type", "Flaot"}, {"min", "zero"}, {"default", 0.5}, {"description", "gain"}};
  try {
    input_spec_from_json("gain", bad);
    ADD_FAILURE() << "a misspelt type was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("\"type\": unknown type \"Flaot\"; did you mean \"Float\"?"),
              std::string::npos)
        << e.what();
  }
  try {
    input_spec_from_json("gain", {{"type", "Float"}, {"min", "zero"}});
    ADD_FAILURE() << "a min that is no number was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("\"min\": expected a number"), std::string::npos) << e.what();
  }
  try {
    input_spec_from_json("gain", {{"type", "Float"}, {"max", 1}, {"default", 2}});
    ADD_FAILURE() << "a default out of its own range was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("\"default\": value 2.0 is out of range: expected at most 1"),
              std::string::npos)
        << e.what();
  }
  // The editor, mid-edit: what can be read is kept, an unknown type is Any.
  const InputSpec lenient = input_spec_from_json("gain", bad, DeclarationReading::lenient);
  EXPECT_EQ(lenient.type->name, "Any");
  EXPECT_FALSE(lenient.min);
  EXPECT_EQ(lenient.default_value, 0.5);
  EXPECT_EQ(lenient.description, "gain");
}

TEST(Binding, SearchPathsTakeAbsoluteFoldersOnly) {
  ::setenv("LOOM_TEST_SEARCH_PATH", "/opt/a::relative/b:/opt/c/../d:", 1);
  ::testing::internal::CaptureStderr();
  const auto path = search_path_from_env("LOOM_TEST_SEARCH_PATH");
  const std::string warned = ::testing::internal::GetCapturedStderr();
  ::unsetenv("LOOM_TEST_SEARCH_PATH");
  ASSERT_EQ(path.size(), 2u);
  EXPECT_EQ(path[0], "/opt/a");
  EXPECT_EQ(path[1], "/opt/d");
  EXPECT_NE(warned.find("LOOM_TEST_SEARCH_PATH entry \"relative/b\" ignored"), std::string::npos) << warned;
  EXPECT_TRUE(search_path_from_env("LOOM_TEST_UNSET_VARIABLE").empty());
}

NodeType type_with(const std::function<void(NodeSpec&)>& declare) {
  NodeType t;
  t.spec.name = "Declared";
  declare(t.spec);
  t.run = [](Inputs&, Outputs&, Context&) {};
  return t;
}

TEST(Binding, DeclarationsAreCheckedOnceWhenRegistered) {
  Registry r;
  EXPECT_THROW(r.add(type_with([](NodeSpec& s) { s.input<double>("a.b", 0.0, "dotted"); }), "p"), Error);
  EXPECT_THROW(r.add(type_with([](NodeSpec& s) { s.output<double>("x.y", "dotted"); }), "p"), Error);
  try {
    r.add(type_with([](NodeSpec& s) {
            s.set_simulation("state", "state").input<double>("state", 0.0, "x").output<int>("state", "y");
          }),
          "p");
    ADD_FAILURE() << "a simulation with input and output of different types was registered";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("simulation state \"state\" -> \"state\""), std::string::npos)
        << error.what();
  }
  EXPECT_NO_THROW(r.add(type_with([](NodeSpec& s) {
                          s.set_simulation("state", "state").input<double>("state", 0.0, "x").output<double>("state",
                                                                                                              "y");
                        }),
                        "p"));
}

// constant -> s1.in0 -> s2.in0 -> ... -> s<n>: every link a lazy input.
json switch_chain(int n) {
  json nodes = {{"c", {{"type", "FloatConstant"}, {"inputs", {{"value", 3.5}}}}}};
  std::string up = "c.value";
  for (int i = 1; i <= n; ++i) {
    const std::string id = "s" + std::to_string(i);
    nodes[id] = {{"type", "Switch"}, {"inputs", {{"index", 0}, {"in0", from(up)}}}};
    up = id + ".value";
  }
  return graph(nodes);
}

TEST(Binding, ALazyChainAtTheLimitRunsOnEveryThread) {
  testing::Engine e;
  Graph g = e.load(switch_chain(kMaxLazyChain));
  for (int threads : {1, 2}) {
    testing::Engine fresh;
    fresh.load(switch_chain(kMaxLazyChain));  // loads the plugins
    EvalResult r = evaluate(fresh, g, {"s" + std::to_string(kMaxLazyChain) + ".value"}, threads);
    ASSERT_TRUE(r.ok()) << threads;
    EXPECT_EQ(r.outputs.begin()->second.at(0).as<double>(), 3.5);
  }
}

TEST(Binding, ALazyChainPastTheLimitIsRefusedByValidationAndByTheEvaluator) {
  testing::Engine e;
  const json doc = switch_chain(2000);
  try {
    e.load(doc);
    ADD_FAILURE() << "validation accepted 2000 chained lazy inputs";
  } catch (const GraphError& error) {
    ASSERT_EQ(error.issues().size(), 1u) << error.what();
    EXPECT_EQ(error.issues()[0].pointer, "/nodes/s" + std::to_string(kMaxLazyChain + 1));
    EXPECT_NE(error.issues()[0].message.find("lazy inputs"), std::string::npos);
  }
  // Unvalidated (a front end that skips validation): a clear failure, no crash.
  Graph g = parse_graph(doc, "chain.json");
  e.load_plugins(node_types_used(g));
  EvalResult r = evaluate(e, g, {"s2000.value"}, 2);
  EXPECT_FALSE(r.ok());
  bool named = false;
  for (const auto& [id, report] : r.nodes) named = named || report.error.find("lazy inputs are nested") != std::string::npos;
  EXPECT_TRUE(named);
}

TEST(Binding, FrameNumbersAreBounded) {
  testing::Engine e;
  Graph g = e.load(graph({{"c", {{"type", "FloatConstant"}, {"inputs", {{"value", 1.0}}}}}}));
  EvalOptions o;
  o.targets = {parse_target("c.value")};
  o.frames = FrameRange{INT_MAX, INT_MAX};
  try {
    e.session().evaluate(g, o);
    ADD_FAILURE() << "frame 2147483647 was evaluated";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("frame numbers lie between"), std::string::npos) << error.what();
  }
  json doc = graph(json::object());
  doc["time"] = {{"start", 2147483647}};
  try {
    parse_graph(doc, "t.json");
    ADD_FAILURE() << "start frame 2147483647 accepted";
  } catch (const GraphError& error) {
    ASSERT_EQ(error.issues().size(), 1u);
    EXPECT_EQ(error.issues()[0].pointer, "/time/start");
    EXPECT_NE(error.issues()[0].message.find("expected between -1000000000 and 1000000000"), std::string::npos)
        << error.issues()[0].message;
  }
}

TEST(Binding, ABadSetValueIsReportedAsComingFromSet) {
  const auto dir = test::temp_dir();
  std::ofstream(dir / "g.json") << graph({{"s", {{"type", "Switch"}, {"inputs", {{"index", 0}, {"in0", 1.0}}}}},
                                          {"p", {{"type", "Print"}, {"inputs", {{"value", from("s.value")}}}}}})
                                       .dump();
  std::string out;
  EXPECT_EQ(test::run_loom("run " + (dir / "g.json").string() + " --set s.index=9 --out " + dir.string(), &out), 2);
  EXPECT_NE(out.find("--set s.index=9: /nodes/s/inputs/index: value 9 is out of range"), std::string::npos) << out;
  EXPECT_EQ(out.find((dir / "g.json").string() + ": /nodes/s/inputs/index"), std::string::npos) << out;
  EXPECT_EQ(test::run_loom("run " + (dir / "g.json").string() + " --set nope.index=1 --out " + dir.string(), &out), 2);
  EXPECT_NE(out.find("--set nope.index=1: /nodes/nope: --set names unknown node \"nope\""), std::string::npos) << out;
}

}  // namespace
}  // namespace loom
