// Groups in the editor window at 1600x900 (issue 25): nodes selected by
// ctrl-clicks and grouped with Ctrl+G, the group entered by a double-click,
// breadcrumbs across the canvas to go back up, an inner input promoted from
// the properties' right-click menu, ungrouped with Ctrl+Shift+G; a group
// file used twice entered from the properties and by a double-click inside
// the document, its inner values shown and one set for one instance; a
// Repeat node drawn with its pins; a save over a file another program
// changed asked about first. Screenshots go to build/editor-screenshots
// (group-*.png, repeat.png).
#include <algorithm>
#include <fstream>
#include <sstream>

#include "ui_harness.hpp"

namespace loom::editor {
namespace {

namespace fs = std::filesystem;
using test::Harness;

std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void double_click(Harness& h, ImVec2 at) {
  h.jump(at);
  for (int i = 0; i < 2; ++i) {
    h.input.mouse_down[0] = true;
    h.frame();
    h.input.mouse_down[0] = false;
    h.frame();
  }
}

TEST(EditorGroups, GroupEnterPromoteLeaveUngroupWithTheMouse) {
  Harness h(1600, 900);
  h.app.open(fs::path(LOOM_SOURCE_DIR) / "graphs" / "warp-checkerboard.json");
  h.frame(3);
  auto& state = h.app.state();
  GraphDocument& doc = h.app.document();
  const std::vector<std::string> chosen = {"idw_inverse", "idw_forward", "idw_forward_fill"};
  h.click(h.app.canvas().node_header(state, chosen[0]));
  h.input.ctrl = true;
  for (std::size_t i = 1; i < chosen.size(); ++i) h.click(h.app.canvas().node_header(state, chosen[i]));
  h.input.ctrl = false;
  ASSERT_EQ(state.selection, std::set<std::string>(chosen.begin(), chosen.end()));
  h.key(GLFW_KEY_G, /*ctrl=*/true);
  ASSERT_TRUE(doc.document().contains("groups")) << h.app.message();
  const std::string group = *state.selection.begin();
  EXPECT_EQ(doc.type_name(group), "Group");
  // One interface input for the board's image, feeding the three warps.
  EXPECT_EQ(doc.document()["groups"]["Group"]["inputs"]["image"]["to"].size(), 3u);
  EXPECT_EQ(doc.link(group, "image")->node, "board");
  h.frame(2);
  h.screenshot("group-made");

  double_click(h, h.app.canvas().node_header(state, group));
  ASSERT_EQ(doc.path(), std::vector<std::string>{group});
  EXPECT_EQ(doc.node_ids(), (std::vector<std::string>{"idw_forward", "idw_forward_fill", "idw_inverse"}));
  h.frame(2);
  ASSERT_EQ(h.app.breadcrumbs().crumbs().size(), 2u);

  // Promote idw_inverse.method from the properties' right-click menu.
  h.click(h.app.canvas().node_header(state, "idw_inverse"));
  h.frame(2);
  auto label = h.app.properties().label_rect("method");
  ASSERT_TRUE(label);
  const ImVec2 at((label->first.x + label->second.x) / 2, (label->first.y + label->second.y) / 2);
  h.click(at, 1);
  h.frame(2);
  h.click(ImVec2(at.x + 30, at.y + 16));
  h.frame(2);
  EXPECT_EQ(doc.promoted_as("idw_inverse", "method"), "method");
  EXPECT_EQ(doc.document()["groups"]["Group"]["inputs"]["method"]["default"], "idw");
  h.frame(2);
  h.screenshot("group-entered");

  // The first crumb goes back to the top graph.
  const auto crumb = h.app.breadcrumbs().crumbs().at(0);
  h.click(ImVec2((crumb.first.x + crumb.second.x) / 2, (crumb.first.y + crumb.second.y) / 2));
  EXPECT_TRUE(doc.path().empty());
  h.frame(2);
  EXPECT_TRUE(h.app.breadcrumbs().crumbs().empty());

  // Ungroup: the three warps are back (prefixed), read by their saves.
  h.click(h.app.canvas().node_header(state, group));
  h.key(GLFW_KEY_G, /*ctrl=*/true, /*shift=*/true);
  EXPECT_FALSE(doc.has_node(group));
  EXPECT_FALSE(doc.document().contains("groups"));
  EXPECT_EQ(doc.link("save_idw_inverse", "image")->node, group + "_idw_inverse");
  EXPECT_EQ(doc.literal(group + "_idw_inverse", "method"), "idw");
  // Undo (ungroup, promote, group) from the keyboard: back to the graph as opened.
  h.key(GLFW_KEY_Z, true);
  h.key(GLFW_KEY_Z, true);
  h.key(GLFW_KEY_Z, true);
  EXPECT_FALSE(doc.dirty());
}

ImVec2 middle(const std::pair<ImVec2, ImVec2>& r) {
  return {(r.first.x + r.second.x) / 2, (r.first.y + r.second.y) / 2};
}

// A group file used twice: y = x * b, soft (x = 3) and hard (x = 5).
fs::path write_group_graph(const std::string& name) {
  const fs::path dir = loom::test::temp_dir() / name;
  fs::create_directories(dir);
  std::ofstream(dir / "scale.json") << R"({"loom": 2,
    "inputs": {"x": {"type": "Float", "default": 1, "to": ["m.a"]}},
    "outputs": {"y": {"from": "m.result"}},
    "nodes": {"m": {"type": "Math", "inputs": {"b": 2, "op": "multiply"}}}})";
  std::ofstream(dir / "g.json") << R"({"loom": 2, "nodes": {
    "soft": {"type": "scale.json", "inputs": {"x": 3}},
    "hard": {"type": "scale.json", "inputs": {"x": 5}},
    "sum": {"type": "Math", "inputs": {"a": {"from": "soft.y"}, "b": {"from": "hard.y"}}}}})";
  return dir / "g.json";
}

// Light text pixels in the lower half of a node's header: the type line.
int type_line_pixels(const Rgba8Image& shot, const Canvas& canvas, const EditorState& state, const std::string& id) {
  const ImVec2 at = canvas.to_screen(state.doc.position(id));
  const float z = canvas.zoom();
  int light = 0;
  for (int y = int(at.y + 24 * z); y < int(at.y + 40 * z); ++y)
    for (int x = int(at.x + 8 * z); x < int(at.x + 200 * z); ++x) {
      const std::uint8_t* p = shot.at(x, y);
      if (std::min({p[0], p[1], p[2]}) > 190) ++light;
    }
  return light;
}

TEST(EditorGroups, AGroupFileIsEnteredInsideTheDocumentWithItsInstancesValues) {
  Harness h(1600, 900);
  const fs::path file = write_group_graph("enter-file");
  h.app.open(file);
  ASSERT_TRUE(h.settle());
  auto& state = h.app.state();
  GraphDocument& doc = h.app.document();
  // The instances' outputs at the top level, and their statuses.
  EXPECT_EQ(state.eval->output("soft", "y").as<double>(), 6);
  ASSERT_NE(state.report("soft"), nullptr);
  EXPECT_EQ(state.report("soft")->status, NodeStatus::ran);
  h.click(h.app.canvas().node_header(state, "soft"));
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(state.viewed_output(0).as<double>(), 6);
  // The header says which group the node is, under its id.
  const Rgba8Image top = h.screenshot("group-file-top");
  EXPECT_GT(type_line_pixels(top, h.app.canvas(), state, "soft"), 20);

  // The properties' "enter group": the editor goes on, inside the document.
  auto enter = h.app.properties().enter_button_rect();
  ASSERT_TRUE(enter);
  h.click(middle(*enter));
  ASSERT_EQ(doc.path(), std::vector<std::string>{"soft"});
  EXPECT_EQ(doc.file(), fs::absolute(file));
  ASSERT_TRUE(h.settle());
  h.click(h.app.canvas().node_header(state, "m"));
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(state.viewed, "m");
  EXPECT_EQ(state.viewed_output(0).as<double>(), 6);  // soft's value, not "not evaluated"
  ASSERT_NE(state.report("m"), nullptr);

  // Set b for this instance only, from the name's right-click menu.
  auto label = h.app.properties().label_rect("b");
  ASSERT_TRUE(label);
  h.click(middle(*label), 1);
  h.frame(2);
  h.click(ImVec2(middle(*label).x + 40, middle(*label).y + 16 + ImGui::GetFrameHeightWithSpacing()));
  h.frame(2);
  ASSERT_EQ(doc.promoted_as("m", "b"), "b") << h.app.message();
  doc.set_instance_input("b", 10);
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(state.viewed_output(0).as<double>(), 30);
  ASSERT_EQ(h.app.breadcrumbs().crumbs().size(), 2u);
  h.screenshot("group-file-entered");

  // Up by the first crumb; a double-click enters the other instance, with its own value.
  h.click(middle(h.app.breadcrumbs().crumbs().at(0)));
  ASSERT_TRUE(doc.path().empty());
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(state.eval->output("hard", "y").as<double>(), 10);
  EXPECT_EQ(state.eval->output("soft", "y").as<double>(), 30);
  double_click(h, h.app.canvas().node_header(state, "hard"));
  ASSERT_EQ(doc.path(), std::vector<std::string>{"hard"});
  EXPECT_EQ(doc.file(), fs::absolute(file));
  ASSERT_TRUE(h.settle());
  h.click(h.app.canvas().node_header(state, "m"));
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(state.viewed_output(0).as<double>(), 10);
}

TEST(EditorGroups, ARepeatNodeIsDrawnWithItsPinsAndItsBodyEntered) {
  Harness h(1600, 900);
  h.app.open(fs::path(LOOM_SOURCE_DIR) / "graphs" / "repeat-smooth.json");
  ASSERT_TRUE(h.settle(240));
  auto& state = h.app.state();
  GraphDocument& doc = h.app.document();
  for (const char* pin : {"count", "mesh", "lambda"})
    EXPECT_TRUE(h.app.canvas().input_socket(state, "loop", pin)) << pin;
  EXPECT_TRUE(h.app.canvas().output_socket(state, "loop", "mesh"));
  ASSERT_NE(state.report("loop"), nullptr);
  EXPECT_EQ(state.report("loop")->status == NodeStatus::ran || state.report("loop")->status == NodeStatus::cached,
            true);
  EXPECT_TRUE(state.eval->output("loop", "mesh"));
  h.screenshot("repeat");
  double_click(h, h.app.canvas().node_header(state, "loop"));
  ASSERT_EQ(doc.path(), std::vector<std::string>{"loop"});
  EXPECT_TRUE(doc.in_repeat_body());
  EXPECT_EQ(doc.node_ids(), std::vector<std::string>{"smooth"});
  h.frame(3);
  h.screenshot("repeat-body");
}

// A group node shows its inner node's progress while that node runs (the
// first evaluation gives the view that says which nodes are inside it).
TEST(EditorGroups, AGroupNodeRunsWhileItsInnerNodeRuns) {
  Harness h(1600, 900, /*test_plugins=*/true);
  h.app.open(test::write_graph(json::parse(R"({"loom": 2, "groups": {"Slow": {
      "inputs": {"ms": {"type": "Int", "default": 1, "to": ["s.ms"]}},
      "outputs": {"value": {"from": "s.value"}},
      "nodes": {"s": {"type": "Sleep", "inputs": {"value": 2}}}}},
    "nodes": {"g": {"type": "Slow"}}})"),
                               "slow-group.json"));
  ASSERT_TRUE(h.settle());
  auto& state = h.app.state();
  EXPECT_EQ(state.live_node("g"), nullptr);
  h.app.document().set_input("g", "ms", 3000);
  const LiveNode* live = nullptr;
  for (int i = 0; i < 400 && !live; ++i) {
    h.frame();
    live = state.live_node("g");
  }
  ASSERT_NE(live, nullptr);
  EXPECT_TRUE(live->running);
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(state.live_node("g"), nullptr);
  EXPECT_EQ(state.report("g")->status, NodeStatus::ran);
  EXPECT_EQ(state.eval->output("g", "value").as<double>(), 2);
}

TEST(EditorGroups, SavingOverAFileChangedOnDiskAsksFirst) {
  Harness h(1600, 900);
  const fs::path file = write_group_graph("conflict");
  h.app.open(file);
  h.frame(2);
  GraphDocument& doc = h.app.document();
  doc.set_input("sum", "b", 1);
  const std::string theirs = R"({"loom": 2, "nodes": {}})";
  std::ofstream(file) << theirs;
  h.key(GLFW_KEY_S, /*ctrl=*/true);
  h.frame(2);
  ASSERT_EQ(h.app.save_conflict(), std::vector<fs::path>{fs::absolute(file)});
  EXPECT_EQ(read_file(file), theirs);  // not overwritten without asking
  EXPECT_TRUE(doc.dirty());
  h.screenshot("save-conflict");
  auto overwrite = h.app.overwrite_button();
  ASSERT_TRUE(overwrite);
  h.click(middle(*overwrite));
  h.frame(2);
  EXPECT_TRUE(h.app.save_conflict().empty());
  EXPECT_EQ(read_file(file), doc.text());
  EXPECT_FALSE(doc.dirty());
}

}  // namespace
}  // namespace loom::editor
