// Groups in the editor window at 1600x900 (issue 25): nodes selected by
// ctrl-clicks and grouped with Ctrl+G, the group entered by a double-click,
// breadcrumbs across the canvas to go back up, an inner input promoted from
// the properties' right-click menu, ungrouped with Ctrl+Shift+G. Screenshots
// go to build/editor-screenshots (group-*.png).
#include "ui_harness.hpp"

namespace loom::editor {
namespace {

namespace fs = std::filesystem;
using test::Harness;

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

}  // namespace
}  // namespace loom::editor
