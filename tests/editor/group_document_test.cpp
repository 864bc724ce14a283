// The editor's groups at the model level (issue 25): group, enter/leave,
// promote, ungroup, undo, the format version on save, group files and the
// library in the search. References are the agreed format written out by
// hand, the registry's declarations, the original graph (round trips) and
// the engine's evaluation of the version-1 graphs before and after.
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "loom/testing.hpp"
#include "test_files.hpp"
#include "model/graph_document.hpp"
#include "model/node_search.hpp"

namespace loom::editor {
namespace {

namespace fs = std::filesystem;

using test::read_text;

fs::path temp_folder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("loom-editor-groups-" + std::to_string(::getpid())) / name;
  fs::create_directories(dir);
  return dir;
}

// m1 -> m2 -> m3 (twice) and board -> warp -> after; {warp, m2} is grouped.
json example() {
  return json::parse(R"({"loom": 1, "nodes": {
    "board": {"type": "Checkerboard", "inputs": {"cells": 4, "size": [32, 32]}, "ui": {"pos": [0, 0]}},
    "warp":  {"type": "ImageWarp", "inputs": {"image": {"from": "board.image"}}, "ui": {"pos": [300, 0]}},
    "after": {"type": "ImageWarp", "inputs": {"image": {"from": "warp.image"}}, "ui": {"pos": [600, 0]}},
    "m1": {"type": "Math", "inputs": {"a": 2, "b": 3}, "ui": {"pos": [0, 300]}},
    "m2": {"type": "Math", "inputs": {"a": {"from": "m1.result"}, "b": 10, "op": "multiply"}, "ui": {"pos": [300, 300]}},
    "m3": {"type": "Math", "inputs": {"a": {"from": "m2.result"}, "b": {"from": "m2.result"}}, "ui": {"pos": [600, 300]}}}})");
}

struct Groups : ::testing::Test {
  testing::Engine engine;
  void SetUp() override {
    engine.load(json::parse(R"({"loom": 1, "nodes": {"b": {"type": "Checkerboard"}, "m": {"type": "Math"},
      "w": {"type": "ImageWarp", "inputs": {"image": {"from": "b.image"}}}}})"));
  }
  // The document without layout and with ids renamed by `rename`.
  static json renamed(json doc, const std::map<std::string, std::string>& rename) {
    json nodes = json::object();
    for (auto& [id, node] : doc["nodes"].items()) {
      node.erase("ui");
      if (node.contains("inputs"))
        for (auto& [input, value] : node["inputs"].items())
          if (value.is_object() && value.contains("from")) {
            const auto l = parse_link(value["from"].get<std::string>());
            value["from"] = (rename.count(l->node) ? rename.at(l->node) : l->node) + "." + l->output;
          }
      nodes[rename.count(id) ? rename.at(id) : id] = node;
    }
    doc["nodes"] = nodes;
    return doc;
  }
};

TEST_F(Groups, CrossingLinksBecomeTheInterfaceWithTheRegistrysTypes) {
  GraphDocument doc(engine.registry());
  doc.load_json(example(), "g.json");
  const std::string id = doc.group({"warp", "m2"});
  EXPECT_EQ(id, "group");
  EXPECT_EQ(doc.type_name(id), "Group");
  const json& def = doc.document()["groups"]["Group"];
  // The format, written out: one input per entering link, one output per inner output read outside.
  EXPECT_EQ(def["inputs"], json::parse(R"({"image": {"type": "Image", "to": ["warp.image"]},
                                           "a": {"type": "Float", "to": ["m2.a"]}})"));
  EXPECT_EQ(def["outputs"], json::parse(R"({"image": {"from": "warp.image"}, "result": {"from": "m2.result"}})"));
  // The declared types, from the registry.
  EXPECT_EQ(def["inputs"]["a"]["type"], engine.registry().find("Math")->spec.find_input("a")->type->name);
  EXPECT_EQ(def["inputs"]["image"]["type"], engine.registry().find("ImageWarp")->spec.find_input("image")->type->name);
  // Inner inputs fed by the interface are unset; literals stay inside.
  EXPECT_EQ(def["nodes"]["m2"]["inputs"], json::parse(R"({"b": 10, "op": "multiply"})"));
  EXPECT_FALSE(def["nodes"]["warp"].contains("inputs"));
  // The group node is wired in and drawn with typed pins.
  EXPECT_EQ(doc.link(id, "image")->node, "board");
  EXPECT_EQ(doc.link(id, "a")->node, "m1");
  EXPECT_EQ(doc.link("m3", "a")->node, id);
  EXPECT_EQ(doc.link("m3", "b")->output, "result");
  EXPECT_EQ(doc.link("after", "image")->output, "image");
  const NodeType* t = doc.node_type(id);
  ASSERT_NE(t, nullptr);
  ASSERT_EQ(t->spec.outputs.size(), 2u);
  EXPECT_EQ(t->spec.outputs[0].type->name, "Image");
  EXPECT_EQ(t->spec.outputs[1].type->name, "Float");
  EXPECT_EQ(doc.link_refusal("m1", "result", id, "image"),
            "type mismatch: m1.result is Float but group.image expects Image");
  EXPECT_EQ(doc.format_version(), 2);
}

TEST_F(Groups, GroupThenUngroupGivesBackTheGraph) {
  GraphDocument doc(engine.registry());
  doc.load_json(example(), "g.json");
  doc.set_input("m2", "b", 7);  // a literal inside the group survives both ways
  const json before = doc.document();
  const std::string id = doc.group({"warp", "m2"});
  const auto added = doc.ungroup(id);
  EXPECT_EQ(added, (std::vector<std::string>{"group_m2", "group_warp"}));
  EXPECT_FALSE(doc.document().contains("groups"));
  EXPECT_EQ(doc.format_version(), 1);
  const json after = renamed(doc.document(), {{"group_m2", "m2"}, {"group_warp", "warp"}});
  EXPECT_EQ(after, renamed(before, {}));
  // Positions come back too: the group node sat at the selection's centre.
  EXPECT_EQ(doc.position("group_m2").x, 300);
  EXPECT_EQ(doc.position("group_m2").y, 300);
  // The engine computes the same: (2 + 3) * 7 twice, added.
  EXPECT_EQ(engine.output<double>(doc.evaluated_part(), "m3.result"), 70.0);
  EXPECT_EQ(engine.output<double>(before, "m3.result"), 70.0);
}

TEST_F(Groups, GroupThenUndoRestoresExactly) {
  GraphDocument doc(engine.registry());
  doc.load_json(example(), "g.json");
  const json before = doc.document();
  const std::string text = doc.text();
  doc.group({"warp", "m2"});
  const json grouped = doc.document();
  ASSERT_TRUE(doc.undo());
  EXPECT_EQ(doc.document(), before);
  EXPECT_EQ(doc.text(), text);
  EXPECT_FALSE(doc.dirty());
  ASSERT_TRUE(doc.redo());
  EXPECT_EQ(doc.document(), grouped);
}

TEST_F(Groups, PromoteAddsTheInterfaceEntryAndItsBinding) {
  GraphDocument doc(engine.registry());
  doc.load_json(example(), "g.json");
  const std::string id = doc.group({"board", "m2"});
  EXPECT_THROW(doc.promote("m2", "b"), Error);  // the top graph has no interface
  ASSERT_TRUE(doc.enter(id));
  EXPECT_TRUE(doc.has_interface());
  // A literal: the interface's default is the literal, so nothing evaluated changes.
  EXPECT_EQ(doc.promote("m2", "b"), "b");
  const InputSpec* cells = engine.registry().find("Checkerboard")->spec.find_input("cells");
  EXPECT_EQ(doc.promote("board", "cells"), "cells");
  const json& inputs = doc.document()["groups"]["Group"]["inputs"];
  EXPECT_EQ(inputs["b"], json::parse(R"({"type": "Float", "default": 10, "description": "right operand",
                                         "to": ["m2.b"]})"));
  EXPECT_EQ(inputs["cells"]["default"], 4);
  EXPECT_EQ(inputs["cells"]["min"], *cells->min);
  EXPECT_EQ(inputs["cells"]["max"], *cells->max);
  EXPECT_EQ(inputs["cells"]["to"], json::array({"board.cells"}));
  EXPECT_TRUE(doc.literal("m2", "b").is_null());
  EXPECT_EQ(doc.promoted_as("m2", "b"), "b");
  EXPECT_THROW(doc.promote("m2", "b"), Error);  // already promoted
  EXPECT_THROW(doc.promote("m2", "a"), Error);  // fed by the interface's link
  // The group node outside has the new input, with the range.
  doc.leave(0);
  const InputSpec* outer = doc.node_type(id)->spec.find_input("cells");
  ASSERT_NE(outer, nullptr);
  EXPECT_EQ(outer->type->name, "Int");
  EXPECT_EQ(outer->max, cells->max);
  // A value set on the group node reaches the inner input when ungrouped.
  doc.set_input(id, "b", 5);
  doc.ungroup(id);
  EXPECT_EQ(doc.literal("group_m2", "b"), json(5));
  EXPECT_EQ(doc.literal("group_board", "cells"), json(4));  // the interface's default
  EXPECT_EQ(engine.output<double>(doc.evaluated_part(), "m3.result"), 50.0);
  doc.undo();
  doc.undo();
  ASSERT_TRUE(doc.enter(id));
  doc.undo();  // the second promote, undone from inside
  EXPECT_FALSE(doc.document()["groups"]["Group"]["inputs"].contains("cells"));
  EXPECT_EQ(doc.path(), std::vector<std::string>{id});
}

TEST_F(Groups, EnterAndLeaveFollowThePath) {
  GraphDocument doc(engine.registry());
  doc.load_json(example(), "g.json");
  EXPECT_FALSE(doc.enter("m1"));  // not a group
  const std::string outer = doc.group({"m1", "m2"});
  ASSERT_TRUE(doc.enter(outer));
  EXPECT_EQ(doc.node_ids(), (std::vector<std::string>{"m1", "m2"}));
  EXPECT_EQ(doc.group_name(), "Group");
  const std::string inner = doc.group({"m2"}, "Inner");
  EXPECT_EQ(doc.node_ids(), (std::vector<std::string>{"inner", "m1"}));
  ASSERT_TRUE(doc.enter(inner));
  EXPECT_EQ(doc.path(), (std::vector<std::string>{"group", "inner"}));
  EXPECT_EQ(doc.path_prefix(), "group.inner.");
  EXPECT_EQ(doc.node_ids(), std::vector<std::string>{"m2"});
  EXPECT_EQ(doc.root_node_ids(), (std::vector<std::string>{"after", "board", "group", "m3", "warp"}));
  // Neither group may go inside the inner one: the search leaves them out.
  EXPECT_THROW(doc.add_node("Group", {0, 0}), Error);
  EXPECT_THROW(doc.add_node("Inner", {0, 0}), Error);
  for (const NodeType* t : doc.group_types()) EXPECT_NE(t->spec.plugin, "group") << t->spec.name;
  doc.leave(1);
  EXPECT_EQ(doc.path(), std::vector<std::string>{"group"});
  ASSERT_TRUE(doc.enter(inner));
  doc.undo();  // the inner grouping: the level entered is gone
  EXPECT_EQ(doc.path(), std::vector<std::string>{"group"});
  EXPECT_EQ(doc.node_ids(), (std::vector<std::string>{"m1", "m2"}));
  doc.leave(0);
  EXPECT_TRUE(doc.path().empty());
  EXPECT_EQ(doc.node_ids().size(), 5u);
}

TEST_F(Groups, SavingWithoutGroupsIsByteIdentical) {
  int files = 0;
  // The copies find the group files the examples name by relative path.
  fs::copy(fs::path(LOOM_SOURCE_DIR) / "graphs" / "groups", temp_folder("examples") / "groups",
           fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  for (const auto& e : fs::directory_iterator(fs::path(LOOM_SOURCE_DIR) / "graphs")) {
    if (e.path().extension() != ".json") continue;
    // The example with the positions the editor adds when it opens a file
    // without them, in the example's own layout: a file opened unchanged.
    GraphDocument placed(engine.registry());
    placed.load(e.path());
    const std::string text = write_json(placed.document(), scan_json_layout(read_text(e.path())));
    const fs::path copy = temp_folder("examples") / e.path().filename();
    std::ofstream(copy, std::ios::binary) << text;
    GraphDocument doc(engine.registry());
    doc.load(copy);
    // Version 1 unless the example uses groups (graphs using graphs/lib's groups say 2).
    EXPECT_EQ(doc.format_version(), json::parse(text)["loom"]) << e.path();
    EXPECT_EQ(doc.text(), text) << e.path();
    ++files;
  }
  EXPECT_GT(files, 20);
  // Grouped, the file says version 2 and opens again as it was saved.
  const fs::path dir = temp_folder("save");
  std::ofstream(dir / "g.json") << example().dump(2) << "\n";
  GraphDocument doc(engine.registry());
  doc.load(dir / "g.json");
  const std::string original = read_text(dir / "g.json");
  // Grouped, undone and saved: the original bytes.
  doc.group({"m2"});
  doc.undo();
  doc.save(dir / "g.json");
  EXPECT_EQ(read_text(dir / "g.json"), original);
  doc.group({"m2"});
  doc.save(dir / "g.json");
  EXPECT_EQ(json::parse(read_text(dir / "g.json"))["loom"], 2);
  GraphDocument again(engine.registry());
  again.load(dir / "g.json");
  EXPECT_EQ(again.evaluated_part(), doc.evaluated_part());
}

TEST_F(Groups, AGroupFileIsWrittenUsedAndUngrouped) {
  const fs::path dir = temp_folder("file");
  GraphDocument doc(engine.registry());
  doc.load_json(example(), dir / "g.json");
  const std::string id = doc.group_to_file({"m2"}, dir / "lib" / "times.json");
  EXPECT_EQ(doc.type_name(id), "lib/times.json");
  EXPECT_EQ(id, "times");
  const json file = json::parse(read_text(dir / "lib" / "times.json"));
  EXPECT_EQ(file["loom"], 2);
  EXPECT_EQ(file["inputs"], json::parse(R"({"a": {"type": "Float", "to": ["m2.a"]}})"));
  EXPECT_EQ(file["outputs"], json::parse(R"({"result": {"from": "m2.result"}})"));
  EXPECT_EQ(doc.group_file(id), dir / "lib" / "times.json");
  // Entered inside the document: the graph stays the document's file.
  ASSERT_TRUE(doc.enter(id));
  EXPECT_EQ(doc.level_file(), fs::weakly_canonical(dir / "lib" / "times.json"));
  EXPECT_EQ(doc.node_ids(), std::vector<std::string>{"m2"});
  doc.leave(0);
  ASSERT_NE(doc.node_type(id), nullptr);
  EXPECT_EQ(doc.node_type(id)->spec.outputs.at(0).type->name, "Float");
  EXPECT_EQ(doc.format_version(), 2);
  doc.ungroup(id);
  EXPECT_EQ(doc.format_version(), 1);
  EXPECT_EQ(engine.output<double>(doc.evaluated_part(), "m3.result"), 100.0);
}

TEST_F(Groups, LibraryGroupsAreInTheSearchWithTheirInterface) {
  const fs::path dir = temp_folder("library");
  std::ofstream(dir / "Studio.json") << R"({"loom": 2, "description": "turns a checkerboard into a lit image",
    "inputs": {"cells": {"type": "Int", "default": 8, "min": 1, "max": 64, "to": ["board.cells"]}},
    "outputs": {"image": {"from": "board.image"}},
    "nodes": {"board": {"type": "Checkerboard"}}})";
  struct GraphPath {  // LOOM_GRAPH_PATH for this test only, however it ends
    explicit GraphPath(const fs::path& dir) { ::setenv("LOOM_GRAPH_PATH", dir.c_str(), 1); }
    ~GraphPath() { ::unsetenv("LOOM_GRAPH_PATH"); }
  } graph_path(dir);
  GraphDocument doc(engine.registry());
  const auto found = search_node_types(doc.group_types(), "Studio");
  ASSERT_FALSE(found.empty());
  EXPECT_EQ(found[0]->spec.name, "Studio");  // the exact name first
  EXPECT_EQ(found[0]->spec.plugin, "library");
  const std::string id = doc.add_node("Studio", {0, 0});
  EXPECT_EQ(id, "studio");
  const NodeType* t = doc.node_type(id);
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->spec.find_input("cells")->max, 64.0);
  EXPECT_EQ(t->spec.outputs.at(0).type->name, "Image");
  EXPECT_EQ(doc.format_version(), 2);
  // An image output links to an image input as any node's would.
  const std::string warp = doc.add_node("ImageWarp", {300, 0});
  EXPECT_EQ(doc.connect(id, "image", warp, "image"), "");
}

TEST_F(Groups, AVersion2FileWithABrokenGroupIsRefusedWithItsPointer) {
  json doc = example();
  doc["loom"] = 2;
  doc["groups"] = {{"G", {{"nodes", {{"x", {{"type", 3}}}}}}}};
  doc["nodes"]["g"] = {{"type", "G"}};
  GraphDocument d(engine.registry());
  try {
    d.load_json(doc, "bad.json");
    FAIL() << "accepted";
  } catch (const GraphError& e) {
    bool found = false;
    for (const GraphIssue& issue : e.issues()) found = found || issue.pointer == "/groups/G/nodes/x/type";
    EXPECT_TRUE(found) << e.what();
  }
}

}  // namespace
}  // namespace loom::editor
