// The editor's UI driven by scripted mouse and keyboard input under Xvfb:
// a whole editing session, the warp tool, and screenshots of every example
// graph checked region by region. Run through run_under_xvfb.sh by ctest.
#include <algorithm>
#include <cmath>
#include <fstream>

#include "loom/image.hpp"
#include "ui_harness.hpp"

namespace loom::editor::test {
namespace {

namespace fs = std::filesystem;

json board_and_warp(int size, json pairs) {
  return {{"loom", 1},
          {"nodes",
           {{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {size, size}}, {"cells", 8}}}, {"ui", {{"pos", {0, 0}}}}}},
            {"warp",
             {{"type", "ImageWarp"},
              {"inputs", {{"image", {{"from", "board.image"}}}, {"method", "idw"}, {"pairs", pairs}}},
              {"ui", {{"pos", {260, 0}}}}}}}}};
}

// Opens the add-node menu with a right click at `at`, searches, takes the first match.
void add_from_menu(Harness& h, ImVec2 at, const std::string& search) {
  h.click(at, 1);
  h.frame(2);  // the search field takes keyboard focus
  h.type(search);
  h.key(GLFW_KEY_ENTER);
}

TEST(EditorUi, ScriptedEditingSession) {
  Harness h;
  const fs::path file = write_graph(board_and_warp(64, json::array()), "session.json");
  h.app.open(file);
  h.frame(2);
  ASSERT_TRUE(h.settle());
  EXPECT_EQ(h.app.state().eval->result.nodes.at("warp").status, NodeStatus::ran);

  // Zoom out around the middle of the canvas to leave room below the nodes.
  h.jump({400, 420});
  h.input.wheel = -3;
  h.frame();

  // Add two nodes from the searchable menu.
  add_from_menu(h, {60, 640}, "Math");
  ASSERT_TRUE(h.app.document().has_node("math")) << h.app.document().document().dump();
  add_from_menu(h, {420, 640}, "math");
  ASSERT_TRUE(h.app.document().has_node("math2"));
  const CanvasPoint placed = h.app.document().position("math");
  const CanvasPoint expected = h.app.canvas().to_canvas({60, 640});
  EXPECT_NEAR(placed.x, expected.x, 1);
  EXPECT_NEAR(placed.y, expected.y, 1);

  // Link math.result -> math2.a by dragging between the sockets.
  auto& state = h.app.state();
  auto out = h.app.canvas().output_socket(state, "math", "result");
  auto in = h.app.canvas().input_socket(state, "math2", "a");
  ASSERT_TRUE(out && in);
  h.drag(*out, *in);
  ASSERT_TRUE(h.app.document().link("math2", "a")) << h.app.document().document().dump();
  EXPECT_EQ(h.app.document().link("math2", "a")->node, "math");

  // An Image output dropped on a Float input is refused, with the reason.
  h.drag(*h.app.canvas().output_socket(state, "board", "image"), *h.app.canvas().input_socket(state, "math", "a"));
  EXPECT_FALSE(h.app.document().link("math", "a"));
  EXPECT_NE(h.app.canvas().refusal().find("type mismatch"), std::string::npos) << h.app.canvas().refusal();

  // Select the warp node and set its IDW power with the slider (range 0.1..16).
  h.click(h.app.canvas().node_header(state, "warp"));
  ASSERT_EQ(state.selection, std::set<std::string>{"warp"});
  h.frame(2);
  auto slider = h.app.properties().widget_rect("idw_power");
  ASSERT_TRUE(slider);
  // The item is the slider's frame (its name is in the table's first column).
  const ImVec2 lo = slider->first;
  const float frame = slider->second.x - lo.x;
  h.click({lo.x + frame * 0.75f, (lo.y + slider->second.y) * 0.5f});
  const json power = h.app.document().literal("warp", "idw_power");
  ASSERT_TRUE(power.is_number()) << h.app.document().document()["nodes"]["warp"].dump();
  EXPECT_NEAR(power.get<double>(), 0.1 + 0.75 * 15.9, 0.6);
  ASSERT_TRUE(h.settle());
  // The engine re-ran only what the edit touched.
  EXPECT_EQ(state.eval->result.nodes.at("warp").status, NodeStatus::ran);
  EXPECT_EQ(state.eval->result.nodes.at("board").status, NodeStatus::cached);
  EXPECT_EQ(state.eval->result.nodes.at("math2").status, NodeStatus::cached);

  // Undo and redo from the keyboard.
  h.jump({60, 300});
  h.key(GLFW_KEY_Z, true);
  EXPECT_TRUE(h.app.document().literal("warp", "idw_power").is_null());
  h.key(GLFW_KEY_Z, true, true);
  EXPECT_EQ(h.app.document().literal("warp", "idw_power"), power);
  h.key(GLFW_KEY_Z, true);
  h.key(GLFW_KEY_Z, true);  // the link
  EXPECT_FALSE(h.app.document().link("math2", "a"));
  h.key(GLFW_KEY_Y, true);
  h.key(GLFW_KEY_Y, true);
  EXPECT_TRUE(h.app.document().link("math2", "a"));
  ASSERT_TRUE(h.settle());
  EXPECT_TRUE(state.eval->result.ok());
  h.screenshot("session");

  // Save with Ctrl+S: the file is the document, with layout, and `loom run` runs it.
  EXPECT_TRUE(h.app.document().dirty());
  h.key(GLFW_KEY_S, true);
  EXPECT_FALSE(h.app.document().dirty());
  std::ifstream saved(file);
  const json doc = json::parse(saved);
  EXPECT_EQ(doc, h.app.document().document());
  EXPECT_EQ(doc["nodes"]["math2"]["inputs"]["a"], json({{"from", "math.result"}}));
  EXPECT_EQ(doc["nodes"]["warp"]["inputs"]["idw_power"], power);
  for (const auto& [id, node] : doc["nodes"].items()) EXPECT_TRUE(node["ui"]["pos"].is_array()) << id;
  std::string output;
  EXPECT_EQ(loom::test::run_loom("run " + file.string() + " --target math2.result", &output), 0) << output;
  EXPECT_EQ(h.app.recent_files().front(), file);
}

TEST(EditorUi, DeleteDuplicateAndBoxSelect) {
  Harness h;
  h.app.open(write_graph(board_and_warp(64, json::array()), "edit.json"));
  h.frame(2);
  auto& state = h.app.state();
  // A box around both nodes selects both.
  const ImVec2 a = h.app.canvas().to_screen(h.app.document().position("board"));
  const float z = h.app.canvas().zoom();
  h.drag({a.x - 15, a.y - 15}, {a.x + 520 * z, a.y + 400 * z});
  EXPECT_EQ(state.selection, (std::set<std::string>{"board", "warp"}));
  h.key(GLFW_KEY_D, true);  // duplicate
  EXPECT_EQ(h.app.document().node_ids().size(), 4u);
  EXPECT_EQ(state.selection.size(), 2u);
  // The copy of warp is fed by the copy of board.
  for (const auto& id : state.selection)
    if (h.app.document().type_name(id) == "ImageWarp") {
      auto l = h.app.document().link(id, "image");
      ASSERT_TRUE(l);
      EXPECT_NE(l->node, "board");
      EXPECT_TRUE(state.selection.count(l->node));
    }
  h.key(GLFW_KEY_DELETE);
  EXPECT_EQ(h.app.document().node_ids(), (std::vector<std::string>{"board", "warp"}));
  h.key(GLFW_KEY_Z, true);
  EXPECT_EQ(h.app.document().node_ids().size(), 4u);
}

TEST(EditorUi, WarpToolDragMovesTheWarp) {
  Harness h;
  // The four corners are held; one pair starts as the identity at (80, 80).
  const json pairs = {{0, 0, 0, 0}, {256, 0, 256, 0}, {0, 256, 0, 256}, {256, 256, 256, 256}, {80, 80, 80, 80}};
  h.app.open(write_graph(board_and_warp(256, pairs), "warp.json"));
  h.frame(2);
  auto& state = h.app.state();
  h.click(h.app.canvas().node_header(state, "warp"));
  ASSERT_EQ(state.viewed, "warp");
  ASSERT_TRUE(h.settle());
  const ImageView view = h.app.image_view();
  ASSERT_GT(view.scale, 0) << "the viewer shows no image";
  const Image board = state.eval->output("board", "image").as<Image>();

  // Drag q of the fifth pair from (80, 80) to (150, 100).
  h.drag(view.to_screen(80, 80), view.to_screen(150, 100), 0, 12);
  const json after = h.app.document().literal("warp", "pairs");
  ASSERT_EQ(after.size(), 5u);
  EXPECT_EQ(after[4][0], 80);  // p stays
  EXPECT_EQ(after[4][1], 80);
  EXPECT_NEAR(after[4][2].get<double>(), 150, 1.0 / view.scale + 0.1);
  EXPECT_NEAR(after[4][3].get<double>(), 100, 1.0 / view.scale + 0.1);
  // One drag is one undo step.
  ASSERT_TRUE(h.settle());

  // Inverse warping shows source p at the new q: the board's color at (80, 80),
  // which differs from what the board has at (150, 100).
  const Image warped = state.eval->output("warp", "image").as<Image>();
  const int qx = int(after[4][2].get<double>()), qy = int(after[4][3].get<double>());
  const cv::Vec3f at_q = warped.pixels.at<cv::Vec3f>(qy, qx);
  const cv::Vec3f source_p = board.pixels.at<cv::Vec3f>(80, 80);
  const cv::Vec3f board_q = board.pixels.at<cv::Vec3f>(qy, qx);
  ASSERT_GT(cv::norm(source_p - board_q), 0.3);
  EXPECT_LT(cv::norm(at_q - source_p), 0.05) << "warped " << at_q << " source " << source_p;
  h.jump({600, 790});  // away from menus and nodes
  h.screenshot("warp-tool");

  // A click on empty image adds a pair; a right click on its end deletes it.
  h.click(view.to_screen(200, 40));
  EXPECT_EQ(h.app.document().literal("warp", "pairs").size(), 6u);
  h.click(view.to_screen(200, 40), 1);
  EXPECT_EQ(h.app.document().literal("warp", "pairs").size(), 5u);
  h.key(GLFW_KEY_Z, true);
  h.key(GLFW_KEY_Z, true);
  h.key(GLFW_KEY_Z, true);  // the drag, in one step
  EXPECT_EQ(h.app.document().literal("warp", "pairs"), pairs);
}

// A graph naming a Python node type (py.MODULE.NAME): opening it asks the
// python plugin, which imports the module; the node then runs like any other.
TEST(EditorUi, OpensAGraphWithAPythonNode) {
  if (!fs::exists(fs::path(LOOM_PLUGIN_DIR) / "libloom_python.so")) GTEST_SKIP() << "python plugin not built";
  Harness h;
  json graph = board_and_warp(32, json::array());
  graph["nodes"]["gamma"] = {{"type", "py.image_math.Gamma"},
                             {"inputs", {{"image", {{"from", "warp.image"}}}, {"gamma", 2.0}}}};
  h.app.open(write_graph(graph, "python.json"));
  ASSERT_TRUE(h.settle());
  EXPECT_TRUE(h.app.state().issues.empty());
  EXPECT_EQ(h.app.state().eval->result.nodes.at("gamma").status, NodeStatus::ran);
}

}  // namespace
}  // namespace loom::editor::test

namespace loom::editor::test {
namespace {

TEST(EditorUi, ValidationErrorsPointAtTheirInput) {
  Harness h;
  json graph = board_and_warp(64, json::array());
  graph["nodes"]["warp"]["inputs"]["method"] = "bilinear";
  h.app.open(write_graph(graph, "invalid.json"));
  ASSERT_TRUE(h.settle());
  const auto& issues = h.app.state().issues;
  ASSERT_TRUE(issues.count("warp"));
  ASSERT_TRUE(issues.at("warp").count("method"));
  EXPECT_NE(issues.at("warp").at("method").find("bilinear"), std::string::npos) << issues.at("warp").at("method");
  // Fixing it in the document clears the issue on the next evaluation.
  h.app.document().set_input("warp", "method", "rbf");
  ASSERT_TRUE(h.settle());
  EXPECT_TRUE(h.app.state().issues.empty());
  EXPECT_EQ(h.app.state().eval->result.nodes.at("warp").status, NodeStatus::ran);
}

}  // namespace
}  // namespace loom::editor::test
