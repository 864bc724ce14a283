// Group instances in the editor (issue 35, item 7): the values computed
// inside a group (a group file used twice) are shown at the top level and
// inside it, a group file is entered inside the document, an inner value is
// set for one instance as `loom run --set` sets it, a Repeat node is declared
// as the engine declares it and its body entered, and a file another program
// changed is not saved over without asking. References: the engine's own
// evaluation of the graph with --set (engine: set_input), the engine's view
// of the validated graph (GraphView::type) and plain arithmetic.
#include <unistd.h>

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "controller/evaluation_controller.hpp"
#include "loom/graph_view.hpp"
#include "loom/testing.hpp"
#include "test_files.hpp"
#include "model/graph_document.hpp"

namespace loom::editor {
namespace {

namespace fs = std::filesystem;

using test::read_text;

// scale.json: y = x * b (b = 2), used by "soft" (x = 3) and "hard" (x = 5).
const char* kScaleGroup = R"({"loom": 2,
  "inputs": {"x": {"type": "Float", "default": 1, "to": ["m.a"]}},
  "outputs": {"y": {"from": "m.result"}},
  "nodes": {"m": {"type": "Math", "inputs": {"b": 2, "op": "multiply"}}}})";

const char* kGraph = R"({"loom": 2, "nodes": {
  "soft": {"type": "scale.json", "inputs": {"x": 3}},
  "hard": {"type": "scale.json", "inputs": {"x": 5}},
  "sum": {"type": "Math", "inputs": {"a": {"from": "soft.y"}, "b": {"from": "hard.y"}}}}})";

struct GroupInstances : ::testing::Test {
  testing::Engine engine;
  fs::path dir, graph, group;
  void SetUp() override {
    engine.load_plugins({"Math", "Time"});
    dir = fs::temp_directory_path() / ("loom-editor-instances-" + std::to_string(::getpid())) /
          ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::create_directories(dir);
    graph = dir / "g.json";
    group = fs::weakly_canonical(dir / "scale.json");
    std::ofstream(group) << kScaleGroup;
    std::ofstream(graph) << kGraph;
  }
  // The editor's evaluation of the document: every node of the top graph and
  // of the level shown, as EditorApp asks for it.
  std::shared_ptr<const Evaluation> evaluate(const GraphDocument& doc, std::optional<FrameRange> frames = {}) {
    EvaluationController controller(engine.registry(), 2);
    EvalRequest r;
    r.document = doc.evaluated_part();
    r.file = doc.file();
    r.output_dir = dir;
    r.preview = doc.path_prefix();
    r.frames = frames;
    controller.submit(std::move(r));
    controller.wait_idle();
    auto done = controller.latest();
    EXPECT_TRUE(done && done->error.empty() && done->issues.empty()) << (done ? done->error : "no result");
    return done;
  }
  // The engine alone on the file as saved, with --set assignments.
  double engine_value(const fs::path& file, const std::vector<std::string>& sets, const std::string& target) {
    Graph g = load_graph_file(file);
    for (const auto& s : sets) set_input(g, s);
    validate_graph(g, engine.registry());
    Session session(engine.registry());
    EvalOptions options;
    options.targets = {parse_target(target)};
    const EvalResult r = session.evaluate(g, options);
    return r.outputs.at(target).at(0).as<double>();
  }
};

TEST_F(GroupInstances, ValuesInsideAGroupFileAreShownAtTheTopAndInside) {
  GraphDocument doc(engine.registry());
  doc.load(graph);
  auto top = evaluate(doc);
  // The instances' outputs and statuses at the top level.
  ASSERT_TRUE(top->output("soft", "y"));
  EXPECT_EQ(top->output("soft", "y").as<double>(), 6);
  EXPECT_EQ(top->output("hard", "y").as<double>(), 10);
  EXPECT_EQ(top->output("sum", "result").as<double>(), 16);
  ASSERT_NE(top->report("soft"), nullptr);
  EXPECT_EQ(top->report("soft")->status, NodeStatus::ran);

  // Entered inside the document: the file stays the graph's, the path is the instance's.
  ASSERT_TRUE(doc.enter("soft"));
  EXPECT_EQ(doc.file(), fs::absolute(graph));
  EXPECT_EQ(doc.path(), std::vector<std::string>{"soft"});
  EXPECT_EQ(doc.level_file(), group);
  EXPECT_EQ(doc.node_ids(), std::vector<std::string>{"m"});
  auto inside = evaluate(doc);
  EXPECT_EQ(inside->output("soft.m", "result").as<double>(), 6);  // this instance's value
  ASSERT_NE(inside->report("soft.m"), nullptr);
  EXPECT_NE(inside->report("soft.m")->status, NodeStatus::pruned);
  doc.leave(0);
  ASSERT_TRUE(doc.enter("hard"));
  EXPECT_EQ(evaluate(doc)->output("hard.m", "result").as<double>(), 10);
  EXPECT_FALSE(doc.dirty());  // entering is not an edit
}

TEST_F(GroupInstances, AnInnerValueSetForOneInstanceIsWhatSetDoes) {
  GraphDocument doc(engine.registry());
  doc.load(graph);
  ASSERT_TRUE(doc.enter("soft"));
  const std::string name = doc.set_for_instance("m", "b", 10);
  EXPECT_EQ(doc.instance_literal(name), 10);
  EXPECT_EQ(doc.promoted_as("m", "b"), name);
  // Every other instance keeps what it had: the interface's default is the old inner value.
  EXPECT_EQ(doc.interface_inputs()[name]["default"], 2);
  EXPECT_EQ(doc.edited_group_files(), std::vector<fs::path>{group});
  EXPECT_EQ(read_text(group), kScaleGroup);  // not written before Save

  // Evaluated as edited (before saving), equal to the engine's --set on the file as it was.
  auto e = evaluate(doc);
  const double reference = engine_value(graph, {"soft.m.b=10"}, "soft.y");
  EXPECT_EQ(reference, 30);
  EXPECT_EQ(e->output("soft", "y").as<double>(), reference);
  EXPECT_EQ(e->output("hard", "y").as<double>(), engine_value(graph, {"soft.m.b=10"}, "hard.y"));
  EXPECT_EQ(e->output("soft.m", "result").as<double>(), 30);

  // Saved: the graph gives soft its value, the group file declares the input;
  // the engine alone agrees.
  doc.save(graph);
  EXPECT_TRUE(doc.edited_group_files().empty());
  EXPECT_EQ(json::parse(read_text(group))["inputs"][name]["to"], json::array({"m.b"}));
  EXPECT_EQ(engine_value(graph, {}, "soft.y"), 30);
  EXPECT_EQ(engine_value(graph, {}, "hard.y"), 10);

  // One undo step takes both files back.
  doc.undo();
  EXPECT_TRUE(doc.instance_literal(name).is_null());
  EXPECT_EQ(doc.promoted_as("m", "b"), "");
  EXPECT_EQ(doc.edited_group_files(), std::vector<fs::path>{group});
}

TEST_F(GroupInstances, EditingTheDefinitionChangesEveryInstanceBeforeItIsSaved) {
  GraphDocument doc(engine.registry());
  doc.load(graph);
  ASSERT_TRUE(doc.enter("soft"));
  doc.set_input("m", "b", 3);
  auto e = evaluate(doc);
  EXPECT_EQ(e->output("soft", "y").as<double>(), 9);
  EXPECT_EQ(e->output("hard", "y").as<double>(), 15);
  doc.save(graph);
  EXPECT_EQ(engine_value(graph, {}, "hard.y"), 15);
}

TEST_F(GroupInstances, GroupOutputsAreShownAtTheFrameStepped) {
  std::ofstream(dir / "clock.json") << R"({"loom": 2,
    "inputs": {"k": {"type": "Float", "default": 1, "to": ["m.b"]}},
    "outputs": {"y": {"from": "m.result"}},
    "nodes": {"t": {"type": "Time"},
              "m": {"type": "Math", "inputs": {"a": {"from": "t.seconds"}, "op": "multiply"}}}})";
  std::ofstream(graph) << R"({"loom": 2, "time": {"start": 1, "end": 10, "fps": 4},
    "nodes": {"c": {"type": "clock.json", "inputs": {"k": 8}}}})";
  GraphDocument doc(engine.registry());
  doc.load(graph);
  for (int frame : {1, 3, 7}) {
    auto e = evaluate(doc, FrameRange{frame, frame});
    ASSERT_TRUE(e->output("c", "y")) << frame;
    EXPECT_DOUBLE_EQ(e->output("c", "y").as<double>(), 8 * (frame - 1) / 4.0) << frame;
  }
}

TEST_F(GroupInstances, RepeatIsDeclaredAsTheEngineDeclaresItAndItsBodyEntered) {
  const json doc_json = json::parse(R"({"loom": 2,
    "groups": {"Halve": {"inputs": {"x": {"type": "Float", "default": 0, "to": ["half.a"]},
                                    "iteration": {"type": "Float", "default": 0, "to": ["spare.a"]}},
                         "outputs": {"x": {"from": "half.result"}},
                         "nodes": {"half": {"type": "Math", "inputs": {"b": 0.5, "op": "multiply"}},
                                   "spare": {"type": "Math"}}}},
    "nodes": {"loop": {"type": "Repeat", "body": "Halve", "inputs": {"count": 3, "x": 8}}}})");
  std::ofstream(graph) << doc_json.dump();
  GraphDocument doc(engine.registry());
  doc.load(graph);
  const NodeType* t = doc.node_type("loop");
  ASSERT_NE(t, nullptr);
  Graph g = load_graph_file(graph);
  validate_graph(g, engine.registry());
  const NodeSpec& reference = GraphView(g, engine.registry()).type("loop").spec;
  ASSERT_EQ(t->spec.inputs.size(), reference.inputs.size());
  for (std::size_t i = 0; i < reference.inputs.size(); ++i) {
    EXPECT_EQ(t->spec.inputs[i].name, reference.inputs[i].name);
    EXPECT_EQ(t->spec.inputs[i].type, reference.inputs[i].type);
  }
  ASSERT_EQ(t->spec.outputs.size(), 1u);
  EXPECT_EQ(t->spec.outputs[0].name, reference.outputs[0].name);
  EXPECT_EQ(t->spec.inputs[0].name, "count");  // "iteration" is Repeat's to feed
  EXPECT_TRUE(doc.is_group_node("loop"));
  EXPECT_EQ(doc.repeat_body("loop"), "Halve");
  EXPECT_EQ(evaluate(doc)->output("loop", "x").as<double>(), 1);

  ASSERT_TRUE(doc.enter("loop"));
  EXPECT_TRUE(doc.in_repeat_body());
  EXPECT_EQ(doc.group_name(), "Halve");
  EXPECT_EQ(doc.node_ids(), (std::vector<std::string>{"half", "spare"}));
  // An inner value for this Repeat node: promoted into the body, given by the node.
  doc.set_for_instance("half", "b", 0.25);
  doc.leave(0);
  EXPECT_EQ(doc.literal("loop", "b"), 0.25);
  EXPECT_EQ(evaluate(doc)->output("loop", "x").as<double>(), 8 * 0.25 * 0.25 * 0.25);
}

TEST_F(GroupInstances, AFileChangedOnDiskSinceItWasReadIsReported) {
  GraphDocument doc(engine.registry());
  doc.load(graph);
  EXPECT_TRUE(doc.changed_on_disk().empty());
  std::ofstream(graph) << R"({"loom": 2, "nodes": {}})";
  EXPECT_EQ(doc.changed_on_disk(), std::vector<fs::path>{fs::absolute(graph)});
  doc.save(graph);  // the model writes when told; EditorApp asks first
  EXPECT_TRUE(doc.changed_on_disk().empty());
  // An edited group file is checked too.
  ASSERT_TRUE(doc.enter("soft"));
  doc.set_input("m", "b", 4);
  std::ofstream(group) << kScaleGroup << "\n";
  EXPECT_EQ(doc.changed_on_disk(), std::vector<fs::path>{group});
}

}  // namespace
}  // namespace loom::editor
