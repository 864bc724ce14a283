// The editor's model without a window: edits, undo/redo, copy/paste and the
// JSON round trip (layout in "ui", files runnable by `loom run`).
#include <fstream>

#include "loom/testing.hpp"
#include "model/graph_document.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom::editor {
namespace {

struct Fixture : ::testing::Test {
  testing::Engine engine;
  void SetUp() override { engine.load_plugins({"Math", "Sleep", "Fail", "Checkerboard", "ImageWarp"}); }
};
using GraphDocumentTest = Fixture;

json two_math() {
  return json::parse(R"({"loom": 1, "description": "kept", "nodes": {
    "a": {"type": "Math", "inputs": {"a": 2, "b": 3}},
    "b": {"type": "Math", "inputs": {"a": {"from": "a.result"}, "b": 10, "op": "multiply"},
          "ui": {"pos": [300, 40], "note": "unknown ui keys survive"}}}})");
}

TEST_F(GraphDocumentTest, AddLinkSetUndoRedoRoundTrip) {
  GraphDocument doc(engine.registry());
  EXPECT_FALSE(doc.dirty());
  const std::string a = doc.add_node("Math", {10, 20});
  const std::string b = doc.add_node("Math", {300, 20});
  EXPECT_EQ(a, "math");
  EXPECT_EQ(b, "math2");
  EXPECT_EQ(doc.connect(a, "result", b, "a"), "");
  doc.set_input(a, "b", 4.5);
  EXPECT_TRUE(doc.dirty());
  EXPECT_EQ(doc.literal(a, "b"), json(4.5));
  ASSERT_TRUE(doc.link(b, "a"));
  EXPECT_EQ(doc.link(b, "a")->node, "math");

  const json full = doc.document();
  EXPECT_TRUE(doc.undo());  // the literal
  EXPECT_TRUE(doc.literal(a, "b").is_null());
  EXPECT_TRUE(doc.undo());  // the link
  EXPECT_FALSE(doc.link(b, "a"));
  EXPECT_TRUE(doc.redo());
  EXPECT_TRUE(doc.redo());
  EXPECT_EQ(doc.document(), full);
  EXPECT_FALSE(doc.can_redo());

  // The document is a graph the engine validates and runs: (0 + 4.5) + 0.
  Graph g = engine.load(doc.document());
  EXPECT_DOUBLE_EQ(engine.output<double>(doc.document(), "math2.result"), 4.5);
  EXPECT_EQ(g.nodes.at("math").ui["pos"], json({10.0, 20.0}));
}

TEST_F(GraphDocumentTest, SaveAndLoadKeepLayoutAndUnknownFields) {
  GraphDocument doc(engine.registry());
  doc.load_json(two_math(), "two.json");
  doc.move_nodes({"b"}, 5, -10);
  doc.set_collapsed("a", true);
  const auto file = test::temp_dir() / "saved.json";
  doc.save(file);
  EXPECT_FALSE(doc.dirty());

  GraphDocument again(engine.registry());
  again.load(file);
  EXPECT_EQ(again.document(), doc.document());
  EXPECT_EQ(again.document()["description"], "kept");
  EXPECT_EQ(again.document()["nodes"]["b"]["ui"]["note"], "unknown ui keys survive");
  EXPECT_DOUBLE_EQ(again.position("b").x, 305);
  EXPECT_DOUBLE_EQ(again.position("b").y, 30);
  EXPECT_TRUE(again.collapsed("a"));
  // Node "a" had no position: it was placed left of its consumer's column.
  EXPECT_LT(again.position("a").x, again.position("b").x + 1);

  // `loom run` reads the saved file as it is.
  std::string output;
  EXPECT_EQ(test::run_loom("run " + file.string() + " --target b.result", &output), 0) << output;
  EXPECT_NE(output.find("50"), std::string::npos) << output;  // (2 + 3) * 10
}

TEST_F(GraphDocumentTest, UndoReturnsToTheSavedStateAsClean) {
  GraphDocument doc(engine.registry());
  doc.load_json(two_math());
  doc.set_input("a", "a", 7);
  EXPECT_TRUE(doc.dirty());
  doc.undo();
  EXPECT_FALSE(doc.dirty());
  doc.redo();
  EXPECT_TRUE(doc.dirty());
}

TEST_F(GraphDocumentTest, MergeKeyCollapsesADragIntoOneStep) {
  GraphDocument doc(engine.registry());
  doc.load_json(two_math());
  const auto start = doc.position("b");
  for (int i = 0; i < 10; ++i) doc.move_nodes({"b"}, 1, 2, "drag");
  doc.end_merge();
  doc.set_input("a", "a", 9, "slider");
  doc.set_input("a", "a", 10, "slider");
  EXPECT_DOUBLE_EQ(doc.position("b").x, start.x + 10);
  EXPECT_TRUE(doc.undo());  // both slider values at once
  EXPECT_EQ(doc.literal("a", "a"), json(2));
  EXPECT_TRUE(doc.undo());  // the whole drag at once
  EXPECT_DOUBLE_EQ(doc.position("b").x, start.x);
  EXPECT_DOUBLE_EQ(doc.position("b").y, start.y);
  EXPECT_FALSE(doc.undo());
}

TEST_F(GraphDocumentTest, LinksAreRefusedWithAReason) {
  GraphDocument doc(engine.registry());
  const auto board = doc.add_node("Checkerboard", {0, 0});
  const auto math = doc.add_node("Math", {0, 0});
  const auto warp = doc.add_node("ImageWarp", {0, 0});
  const std::string mismatch = doc.connect(board, "image", math, "a");
  EXPECT_NE(mismatch.find("type mismatch"), std::string::npos) << mismatch;
  EXPECT_NE(mismatch.find("Image"), std::string::npos) << mismatch;
  EXPECT_EQ(doc.connect(board, "image", warp, "image"), "");
  // math2 <- math, then math <- math2 would close a cycle.
  const auto math2 = doc.add_node("Math", {0, 0});
  EXPECT_EQ(doc.connect(math, "result", math2, "a"), "");
  EXPECT_NE(doc.connect(math2, "result", math, "b").find("cycle"), std::string::npos);
  EXPECT_NE(doc.connect(math, "result", math, "b").find("cycle"), std::string::npos);
  EXPECT_FALSE(doc.link(math, "b"));
}

TEST_F(GraphDocumentTest, DeletingANodeUnlinksItsConsumers) {
  GraphDocument doc(engine.registry());
  doc.load_json(two_math());
  doc.remove_nodes({"a"});
  EXPECT_FALSE(doc.has_node("a"));
  EXPECT_FALSE(doc.link("b", "a"));
  EXPECT_NO_THROW(engine.load(doc.document()));  // still a valid graph
  doc.undo();
  EXPECT_TRUE(doc.has_node("a"));
  EXPECT_TRUE(doc.link("b", "a"));
}

TEST_F(GraphDocumentTest, CopyPasteRenamesAndKeepsInnerLinks) {
  GraphDocument doc(engine.registry());
  doc.load_json(two_math());
  const json clip = doc.copy({"a", "b"});
  // The clipboard is itself a graph.
  EXPECT_NO_THROW(engine.load(clip));
  const auto added = doc.paste(clip, 50, 0);
  ASSERT_EQ(added.size(), 2u);
  EXPECT_EQ(doc.node_ids().size(), 4u);
  // The pasted b links to the pasted a, not to the original.
  const std::string new_b = added[1];
  ASSERT_TRUE(doc.link(new_b, "a"));
  EXPECT_EQ(doc.link(new_b, "a")->node, added[0]);
  EXPECT_NE(added[0], "a");
  EXPECT_DOUBLE_EQ(engine.output<double>(doc.document(), new_b + ".result"), 50);

  // Copying only b drops its link to a (outside the selection).
  const json lone = doc.copy({"b"});
  EXPECT_FALSE(lone["nodes"]["b"]["inputs"].contains("a"));
  const auto dup = doc.duplicate({"b"});
  ASSERT_EQ(dup.size(), 1u);
  EXPECT_FALSE(doc.link(dup[0], "a"));
  EXPECT_EQ(doc.literal(dup[0], "op"), json("multiply"));

  EXPECT_THROW(doc.paste(json{{"not", "a graph"}}, 0, 0), GraphError);
}

TEST_F(GraphDocumentTest, ResetInputFallsBackToTheDefault) {
  GraphDocument doc(engine.registry());
  doc.load_json(two_math());
  doc.reset_input("b", "op");
  EXPECT_TRUE(doc.literal("b", "op").is_null());
  EXPECT_DOUBLE_EQ(engine.output<double>(doc.document(), "b.result"), 15);  // 5 + 10
}

TEST_F(GraphDocumentTest, BadFilesAreRefusedWithTheirName) {
  GraphDocument doc(engine.registry());
  const auto file = test::temp_dir() / "broken.json";
  std::ofstream(file) << "{\"loom\": 1, \"nodes\": ";
  try {
    doc.load(file);
    FAIL() << "loaded a broken file";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.json"), std::string::npos) << e.what();
  }
  EXPECT_THROW(doc.load(test::temp_dir() / "absent.json"), GraphError);
  EXPECT_TRUE(doc.node_ids().empty());  // the document is unchanged
  EXPECT_THROW(doc.add_node("NoSuchNode", {0, 0}), Error);
}

}  // namespace
}  // namespace loom::editor

namespace loom::editor {
namespace {

TEST_F(GraphDocumentTest, SetInputsIsOneStepAndNullUnsets) {
  GraphDocument doc(engine.registry());
  doc.load_json(two_math());
  doc.set_inputs("b", {{"op", nullptr}, {"b", 1}});
  EXPECT_TRUE(doc.literal("b", "op").is_null());
  EXPECT_EQ(doc.literal("b", "b"), json(1));
  EXPECT_TRUE(doc.undo());
  EXPECT_EQ(doc.literal("b", "op"), json("multiply"));
  EXPECT_EQ(doc.literal("b", "b"), json(10));
  EXPECT_FALSE(doc.undo());
}

TEST_F(GraphDocumentTest, LayoutIsNotPartOfWhatIsEvaluated) {
  GraphDocument doc(engine.registry());
  doc.load_json(two_math());
  const json before = doc.evaluated_part();
  doc.move_nodes({"a", "b"}, 10, 10);
  doc.set_collapsed("b", true);
  EXPECT_EQ(doc.evaluated_part(), before);
  doc.set_input("a", "a", 1);
  EXPECT_NE(doc.evaluated_part(), before);
  EXPECT_EQ(doc.evaluated_part()["description"], "kept");
}

}  // namespace
}  // namespace loom::editor
