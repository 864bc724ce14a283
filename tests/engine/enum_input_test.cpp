// Typed enum inputs: choices declared once with their C++ values
// (NodeSpec::enum_input<E>), read with Inputs::get<E>. Graph files, `loom
// nodes` and the engine's checks see the same strings as before.
#include <gtest/gtest.h>

#include "loom/registry.hpp"
#include "loom/testing.hpp"

namespace loom {
namespace {

// Values far from 0, 1, 2: a mapping by position in the list would show.
enum class Shape { circle = 3, square = 7, star = -2 };
enum class Other { circle, square, star };  // the same names, another enum

const EnumChoices<Shape> kShapes = {{Shape::circle, "circle"}, {Shape::square, "square"}, {Shape::star, "star"}};

// How the probe node reads its "shape" input; a node bug per case.
enum class Read { typed, other_enum, not_an_enum, strings_only };

void declare_probe(NodeSpec& s) {
  s.describe("Reads its enum inputs as the test asks.")
      .enum_input("shape", Shape::square, kShapes, "a typed enum")
      .enum_input("plain", "x", {"x", "y"}, "an enum of strings only")
      .input<int>("count", 1, "not an enum")
      .enum_input("read", Read::typed,
                  {{Read::typed, "typed"},
                   {Read::other_enum, "other_enum"},
                   {Read::not_an_enum, "not_an_enum"},
                   {Read::strings_only, "strings_only"}},
                  "which read to do")
      .output<int>("value", "the C++ value read")
      .output<std::string>("name", "the choice's name, read as a string");
}

void run_probe(Inputs& in, Outputs& out, Context&) {
  int value = 0;
  switch (in.get<Read>("read")) {
    case Read::typed: value = static_cast<int>(in.get<Shape>("shape")); break;
    case Read::other_enum: value = static_cast<int>(in.get<Other>("shape")); break;
    case Read::not_an_enum: value = static_cast<int>(in.get<Shape>("count")); break;
    case Read::strings_only: value = static_cast<int>(in.get<Shape>("plain")); break;
  }
  out.set("value", value);
  out.set("name", in.get<std::string>("shape"));
}

struct ProbeEngine : testing::Engine {
  ProbeEngine() {
    NodeType t;
    t.spec.name = "EnumProbe";
    declare_probe(t.spec);
    t.run = &run_probe;
    registry().add(std::move(t), "enum_input_test");
  }
};

json link(const std::string& from) { return {{"from", from}}; }
json graph(json nodes) { return {{"loom", 1}, {"nodes", std::move(nodes)}}; }

// Runs the probe; returns its status and error, and the value it read.
struct Outcome {
  NodeStatus status;
  std::string error;
  int value = 0;
  std::string name;
};
Outcome run(ProbeEngine& e, const json& document) {
  testing::Run r = e.run(document, {"probe.value", "probe.name"});
  Outcome o;
  o.status = r.status("probe");
  o.error = r.error("probe");
  if (r.ok()) {
    o.value = r.output<int>("probe.value");
    o.name = r.output<std::string>("probe.name");
  }
  return o;
}

TEST(EnumInput, DeclaresTheSameStringsAsBefore) {
  ProbeEngine e;
  const NodeType* t = e.registry().find("EnumProbe");
  ASSERT_NE(t, nullptr);
  const InputSpec* shape = t->spec.find_input("shape");
  ASSERT_NE(shape, nullptr);
  EXPECT_EQ(shape->type, &enum_type());
  EXPECT_EQ(shape->default_value, json("square"));
  EXPECT_EQ(shape->choices, (std::vector<std::string>{"circle", "square", "star"}));
  // What `loom nodes --json` prints: strings only, as for an enum of strings.
  bool described = false;
  const json description = describe_node_type(*t);
  for (const json& in : description["inputs"])
    if (in["name"] == "shape") {
      described = true;
      EXPECT_EQ(in["type"], "Enum");
      EXPECT_EQ(in["default"], "square");
      EXPECT_EQ(in["choices"], json({"circle", "square", "star"}));
    }
  EXPECT_TRUE(described);
}

TEST(EnumInput, GetReturnsTheValueOfALiteralAndOfTheDefault) {
  ProbeEngine e;
  Outcome o = run(e, graph({{"probe", {{"type", "EnumProbe"}, {"inputs", {{"shape", "star"}}}}}}));
  ASSERT_EQ(o.status, NodeStatus::ran) << o.error;
  EXPECT_EQ(o.value, -2);
  EXPECT_EQ(o.name, "star");  // get<std::string> still reads the choice's name

  o = run(e, graph({{"probe", {{"type", "EnumProbe"}}}}));
  ASSERT_EQ(o.status, NodeStatus::ran) << o.error;
  EXPECT_EQ(o.value, 7);
  EXPECT_EQ(o.name, "square");
}

TEST(EnumInput, GetReturnsTheValueOfALinkedString) {
  ProbeEngine e;
  Outcome o = run(e, graph({{"s", {{"type", "StringConstant"}, {"inputs", {{"value", "circle"}}}}},
                            {"probe", {{"type", "EnumProbe"}, {"inputs", {{"shape", link("s.value")}}}}}}));
  ASSERT_EQ(o.status, NodeStatus::ran) << o.error;
  EXPECT_EQ(o.value, 3);
  EXPECT_EQ(o.name, "circle");
}

TEST(EnumInput, AnUnknownLinkedStringFailsTheNodeNamingInputAndChoices) {
  ProbeEngine e;
  Outcome o = run(e, graph({{"s", {{"type", "StringConstant"}, {"inputs", {{"value", "hexagon"}}}}},
                            {"probe", {{"type", "EnumProbe"}, {"inputs", {{"shape", link("s.value")}}}}}}));
  EXPECT_EQ(o.status, NodeStatus::failed);
  EXPECT_NE(o.error.find("input \"shape\""), std::string::npos) << o.error;
  EXPECT_NE(o.error.find("\"hexagon\" is not one of the choices: \"circle\", \"square\", \"star\""),
            std::string::npos)
      << o.error;
}

TEST(EnumInput, AnUnknownLiteralIsRefusedWhenTheGraphLoads) {
  ProbeEngine e;
  try {
    e.load(graph({{"probe", {{"type", "EnumProbe"}, {"inputs", {{"shape", "hexagon"}}}}}}));
    FAIL() << "the graph was accepted";
  } catch (const GraphError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("/nodes/probe/inputs/shape"), std::string::npos) << what;
    EXPECT_NE(what.find("\"hexagon\" is not one of the choices: \"circle\", \"square\", \"star\""),
              std::string::npos)
        << what;
  }
}

TEST(EnumInput, GetOfAnotherEnumIsAClearError) {
  ProbeEngine e;
  Outcome o = run(e, graph({{"probe", {{"type", "EnumProbe"}, {"inputs", {{"read", "other_enum"}}}}}}));
  EXPECT_EQ(o.status, NodeStatus::failed);
  EXPECT_NE(o.error.find("input \"shape\" is declared with values of enum loom::(anonymous namespace)::Shape"),
            std::string::npos)
      << o.error;
  EXPECT_NE(o.error.find("a bug in node EnumProbe: get<loom::(anonymous namespace)::Other>(\"shape\")"),
            std::string::npos)
      << o.error;
}

TEST(EnumInput, GetOfAnEnumOnAnotherInputIsAClearError) {
  ProbeEngine e;
  Outcome o = run(e, graph({{"probe", {{"type", "EnumProbe"}, {"inputs", {{"read", "not_an_enum"}}}}}}));
  EXPECT_EQ(o.status, NodeStatus::failed);
  EXPECT_NE(o.error.find("input \"count\" is Int, not an enum"), std::string::npos) << o.error;
  EXPECT_NE(o.error.find("a bug in node EnumProbe"), std::string::npos) << o.error;

  o = run(e, graph({{"probe", {{"type", "EnumProbe"}, {"inputs", {{"read", "strings_only"}}}}}}));
  EXPECT_EQ(o.status, NodeStatus::failed);
  EXPECT_NE(o.error.find("input \"plain\" is an enum declared with strings only: read it with get<std::string>"),
            std::string::npos)
      << o.error;
}

TEST(EnumInput, ADeclarationWithoutItsDefaultOrWithATwiceNamedChoiceIsRefused) {
  NodeSpec s;
  s.name = "Bad";
  try {
    s.enum_input("shape", Shape::star, {{Shape::circle, "circle"}, {Shape::square, "square"}}, "text");
    FAIL() << "a default outside the choices was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("node Bad, enum input \"shape\": the default value is not one of the choices"),
              std::string::npos)
        << error.what();
  }
  try {
    s.enum_input("shape", Shape::circle, {{Shape::circle, "round"}, {Shape::square, "round"}}, "text");
    FAIL() << "a choice named twice was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("the choice \"round\" is named twice"), std::string::npos)
        << error.what();
  }
  EXPECT_TRUE(s.inputs.empty());
}

}  // namespace
}  // namespace loom
