// What a first hour with the editor met (issue 28, items 4-8 and 12), driven
// under Xvfb at 1600x900: legible text at the opening zoom (real glyphs,
// contrast measured on the screenshot), shortcuts wherever the mouse is, the
// search's ranking, splitters, a properties panel that cuts nothing off,
// new nodes in free space, doubles typed exactly, and a saved file that
// diffs in one line.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "loom/image.hpp"
#include "ui/canvas_geometry.hpp"
#include "ui/fonts.hpp"
#include "ui_harness.hpp"

namespace loom::editor::test {
namespace {

namespace fs = std::filesystem;

// A graph of `chains` image chains (Checkerboard -> ImageWarp -> ... ), no
// positions: laid out on opening as a user's hand-written file would be.
json image_chains(int chains, int length) {
  json nodes = json::object();
  for (int c = 0; c < chains; ++c) {
    const std::string board = "board" + std::to_string(c);
    nodes[board] = {{"type", "Checkerboard"}, {"inputs", {{"size", {32, 32}}, {"cells", 2 + c}}}};
    std::string last = board;
    for (int i = 1; i < length; ++i) {
      const std::string id = "warp" + std::to_string(c) + "_" + std::to_string(i);
      nodes[id] = {{"type", "ImageWarp"},
                   {"inputs", {{"image", {{"from", last + ".image"}}}, {"method", i % 2 ? "idw" : "rbf"}}}};
      last = id;
    }
  }
  return {{"loom", 1}, {"nodes", nodes}};
}

// Relative luminance (WCAG 2) of an 8-bit sRGB colour, and the contrast of two.
double luminance(const std::uint8_t* p) {
  auto lin = [](double c) { c /= 255; return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
  return 0.2126 * lin(p[0]) + 0.7152 * lin(p[1]) + 0.0722 * lin(p[2]);
}
double contrast(double a, double b) { return (std::max(a, b) + 0.05) / (std::min(a, b) + 0.05); }

// The brightest and darkest pixels of a screen rectangle.
std::pair<double, double> extremes(const Rgba8Image& shot, ImVec2 lo, ImVec2 hi) {
  double bright = 0, dark = 1;
  for (int y = std::max(0, int(lo.y)); y < std::min(shot.height, int(hi.y)); ++y)
    for (int x = std::max(0, int(lo.x)); x < std::min(shot.width, int(hi.x)); ++x) {
      const double l = luminance(shot.at(x, y));
      bright = std::max(bright, l);
      dark = std::min(dark, l);
    }
  return {bright, dark};
}

// Opening a 13-node and a 40-node graph: the zoom keeps text at 12 px or
// more (the 40-node graph is scrolled, not shrunk), every input row of a
// visible node has text in it, and that text stands out from the node body
// by a WCAG contrast of 4.5 or more, measured on the screenshot.
void check_legible(Harness& h, const std::string& name) {
  Canvas& canvas = h.app.canvas();
  EXPECT_GE(canvas.zoom(), canvas_geometry::kMinFitZoom);
  EXPECT_GE(kUiFontSize * canvas.zoom(), 12.0f);
  h.jump({1590, 890});
  const Rgba8Image shot = h.screenshot(name);
  auto& state = h.app.state();
  const float z = canvas.zoom();
  int rows = 0, legible = 0;
  for (const auto& id : h.app.document().node_ids()) {
    const ImVec2 a = canvas.to_screen(h.app.document().position(id));
    if (a.x < 0 || a.y < 60 || a.x + canvas_geometry::kWidth * z > h.app.pane_rects().left || a.y + 200 * z > 890)
      continue;
    const NodeType* t = h.app.document().node_type(id);
    for (const auto& in : t->spec.inputs) {
      const ImVec2 socket = *canvas.input_socket(state, id, in.name);
      const ImVec2 lo(socket.x + 8 * z, socket.y - 7 * z), hi(socket.x + 100 * z, socket.y + 7 * z);
      if (hi.y > h.app.pane_rects().at.y + h.app.pane_rects().size.y - 12) break;  // under the pane's edge
      ++rows;
      const auto [bright, dark] = extremes(shot, lo, hi);
      if (contrast(bright, dark) >= 4.5)
        ++legible;
      else
        ADD_FAILURE() << name << ": " << id << "." << in.name << " contrast " << contrast(bright, dark) << " at "
                      << lo.x << ", " << lo.y;
    }
  }
  EXPECT_GT(rows, 8) << name;
  EXPECT_EQ(legible, rows) << name << ": input names too faint or left out";
}

TEST(EditorUsability, LegibleAtTheOpeningZoomWithRealGlyphs) {
  Harness h(1600, 900);
  // The glyphs node descriptions use are in the font (not "?").
  for (ImWchar c : {0x03BB, 0x03A3, 0x2212, 0x00B2, 0x03B8, 0x00D7})
    EXPECT_NE(ImGui::GetIO().Fonts->Fonts[0]->FindGlyphNoFallback(c), nullptr) << std::hex << c;
  EXPECT_GE(ImGui::GetFontSize(), 15.0f);

  json thirteen = image_chains(3, 4);
  thirteen["nodes"]["sum"] = {{"type", "Math"}, {"inputs", {{"a", 2}, {"b", 0.5}}}};
  h.app.open(write_graph(thirteen, "graph13.json"));
  ASSERT_EQ(h.app.document().node_ids().size(), 13u);
  ASSERT_TRUE(h.settle());
  check_legible(h, "graph-13-nodes");

  h.app.open(write_graph(image_chains(5, 8), "graph40.json"));
  ASSERT_EQ(h.app.document().node_ids().size(), 40u);
  ASSERT_TRUE(h.settle());
  check_legible(h, "graph-40-nodes");
}

TEST(EditorUsability, ShortcutsWorkWhereverTheMouseIs) {
  Harness h(1600, 900);
  const fs::path file = write_graph(image_chains(1, 2), "keys.json");
  h.app.open(file);
  ASSERT_TRUE(h.settle());
  auto& state = h.app.state();
  GraphDocument& doc = h.app.document();
  const PaneRects panes = h.app.pane_rects();
  const ImVec2 over_viewer(panes.left + 300, panes.props + 300), over_properties(panes.left + 300, 120);

  h.click(h.app.canvas().node_header(state, "warp0_1"));
  ASSERT_EQ(state.selection, std::set<std::string>{"warp0_1"});
  h.jump(over_viewer);
  h.key(GLFW_KEY_DELETE);
  EXPECT_FALSE(doc.has_node("warp0_1")) << "Delete over the viewer";
  h.jump(over_properties);
  h.key(GLFW_KEY_Z, true);
  EXPECT_TRUE(doc.has_node("warp0_1")) << "Ctrl+Z over the properties";
  h.key(GLFW_KEY_Z, true, true);
  EXPECT_FALSE(doc.has_node("warp0_1")) << "Ctrl+Shift+Z";
  h.key(GLFW_KEY_Z, true);

  // Tab over the properties opens the search; the new node takes no text focus.
  h.key(GLFW_KEY_TAB);
  ASSERT_TRUE(h.app.canvas().menu_open());
  h.type("math");
  h.key(GLFW_KEY_ENTER);
  h.frame(2);
  ASSERT_TRUE(doc.has_node("math"));
  EXPECT_FALSE(ImGui::GetIO().WantTextInput) << "a text field kept the keyboard after adding";
  h.jump(over_viewer);
  h.key(GLFW_KEY_DELETE);
  EXPECT_FALSE(doc.has_node("math")) << "Delete right after adding from the search";

  // In a text field, Delete edits the text and leaves the node alone.
  h.click(h.app.canvas().node_header(state, "warp0_1"));
  h.frame(2);
  auto pairs = h.app.properties().widget_rect("pairs");
  ASSERT_TRUE(pairs);
  h.click({(pairs->first.x + pairs->second.x) / 2, (pairs->first.y + pairs->second.y) / 2});
  h.frame();
  EXPECT_TRUE(ImGui::GetIO().WantTextInput);
  h.key(GLFW_KEY_DELETE);
  EXPECT_TRUE(doc.has_node("warp0_1"));
  h.key(GLFW_KEY_ESCAPE);
  h.frame(2);

  // Ctrl+S over the viewer saves.
  h.jump(over_viewer);
  ASSERT_TRUE(doc.dirty());
  h.key(GLFW_KEY_S, true);
  EXPECT_FALSE(doc.dirty());
}

TEST(EditorUsability, SearchOffersNamesBeforeDescriptions) {
  Harness h(1600, 900);
  h.jump({300, 400});
  h.key(GLFW_KEY_TAB);
  h.frame(2);
  h.type("smooth");
  h.key(GLFW_KEY_ENTER);
  const auto ids = h.app.document().node_ids();
  ASSERT_EQ(ids.size(), 1u);
  EXPECT_EQ(h.app.document().type_name(ids[0]), "SmoothMesh");
}

TEST(EditorUsability, PanesResizeAndPropertiesCutNothingOff) {
  Harness h(1600, 900);
  h.app.document().add_node("Render", {40, 40});
  h.app.document().set_input("render", "shadow_resolution", 1024);
  h.frame(2);
  h.click(h.app.canvas().node_header(h.app.state(), "render"));
  h.frame(3);
  auto check = [&](const char* where) {
    const PropertyPanel& p = h.app.properties();
    const auto visible = p.visible_rect();
    const NodeType* t = h.app.document().node_type("render");
    int checked = 0;
    for (const auto& in : t->spec.inputs) {
      auto label = p.label_rect(in.name), widget = p.widget_rect(in.name);
      if (!label || !widget || label->second.y > visible.second.y - 20) continue;  // below the fold: scrolled to
      ++checked;
      EXPECT_NEAR(label->second.x - label->first.x, ImGui::CalcTextSize(in.name.c_str()).x, 1) << where << in.name;
      EXPECT_LE(label->second.x, widget->first.x) << where << ": " << in.name << " is covered by its widget";
      EXPECT_LE(label->second.x, visible.second.x) << where << in.name;
      if (auto button = p.button_rect(in.name)) {
        EXPECT_GE(button->first.x, widget->second.x) << where << in.name;
        EXPECT_NEAR(button->second.x - button->first.x,
                    ImGui::CalcTextSize("reset").x + ImGui::GetStyle().FramePadding.x * 2, 1) << where << in.name;
      }
    }
    EXPECT_GT(checked, 4) << where;
    ASSERT_TRUE(p.button_rect("shadow_resolution")) << where;
  };
  check("wide: ");
  // Drag the canvas/properties border 250 px right, the properties/viewer one down.
  const PaneRects before = h.app.pane_rects();
  h.drag({before.at.x + before.left, before.at.y + 400}, {before.at.x + before.left + 250, before.at.y + 400});
  const PaneRects after = h.app.pane_rects();
  EXPECT_NEAR(after.left, before.left + 250, 2);
  const ImVec2 border(after.at.x + after.left + 200, after.at.y + after.props);
  h.drag(border, {border.x, border.y + 150});
  EXPECT_NEAR(h.app.pane_rects().props, after.props + 150, 2);
  h.frame(3);
  check("narrow: ");
  h.screenshot("narrow-properties");
}

TEST(EditorUsability, NewNodesGoToFreeSpaceNearTheMouse) {
  Harness h(1600, 900);
  h.app.open(write_graph(image_chains(1, 3), "free.json"));
  h.frame(3);
  auto& state = h.app.state();
  const ImVec2 on_node = h.app.canvas().node_header(state, "warp0_1");
  h.jump(on_node);
  h.key(GLFW_KEY_TAB);
  h.frame(2);
  h.type("Checkerboard");
  h.key(GLFW_KEY_ENTER);
  ASSERT_TRUE(h.app.document().has_node("checkerboard"));
  h.frame(2);
  const Canvas& canvas = h.app.canvas();
  GraphDocument& doc = h.app.document();
  auto height = [&](const std::string& id) {
    const NodeType* t = doc.node_type(id);
    return canvas_geometry::kHeader + canvas_geometry::kRow * float(t->spec.inputs.size() + t->spec.outputs.size()) +
           canvas_geometry::kFooter;
  };
  const CanvasPoint p = doc.position("checkerboard");
  for (const auto& id : doc.node_ids()) {
    if (id == "checkerboard") continue;
    const CanvasPoint q = doc.position(id);
    const bool overlap = p.x < q.x + canvas_geometry::kWidth && q.x < p.x + canvas_geometry::kWidth &&
                         p.y < q.y + height(id) && q.y < p.y + height("checkerboard");
    EXPECT_FALSE(overlap) << "the new node lies on " << id;
  }
  const ImVec2 a = canvas.to_screen(p);
  EXPECT_LT(std::hypot(a.x - on_node.x, a.y - on_node.y), 500) << "placed far from the mouse";
}

// A double typed into a drag field is stored as typed (the panel used a
// float), and the saved file differs from the hand-written one in one line.
TEST(EditorUsability, TypedDoubleIsExactAndTheSaveDiffsInOneLine) {
  Harness h(1600, 900);
  const std::string text =
      "{\n"
      "  \"loom\": 1,\n"
      "  \"nodes\": {\n"
      "    \"board\": {\"type\": \"Checkerboard\", \"inputs\": {\"size\": [64, 64]}, \"ui\": {\"pos\": [40, 40]}},\n"
      "    \"warp\": {\"type\": \"ImageWarp\", \"inputs\": {\"image\": {\"from\": \"board.image\"}, \"lambda\": 0},\n"
      "             \"ui\": {\"pos\": [320, 40]}}\n"
      "  }\n"
      "}\n";
  const fs::path file = loom::test::temp_dir() / "hand.json";
  std::ofstream(file) << text;
  h.app.open(file);
  h.frame(2);
  h.click(h.app.canvas().node_header(h.app.state(), "warp"));
  h.frame(2);
  auto field = h.app.properties().widget_rect("lambda");
  ASSERT_TRUE(field);
  // Ctrl+click turns the drag field into a text field with its text selected.
  h.input.ctrl = true;
  h.click({(field->first.x + field->second.x) / 2, (field->first.y + field->second.y) / 2});
  h.input.ctrl = false;
  h.frame();
  h.type("0.1234567890123");
  h.key(GLFW_KEY_ENTER);
  h.frame(2);
  ASSERT_TRUE(h.app.document().literal("warp", "lambda").is_number());
  EXPECT_EQ(h.app.document().literal("warp", "lambda").get<double>(), 0.1234567890123);
  h.jump({1500, 880});
  h.key(GLFW_KEY_S, true);
  std::ifstream in(file);
  std::stringstream read;
  read << in.rdbuf();
  const std::string saved = read.str();
  std::istringstream a(text), b(saved);
  int changed = 0, lines = 0;
  for (std::string x, y; std::getline(a, x) && std::getline(b, y); ++lines) changed += x != y;
  EXPECT_EQ(changed, 1) << saved;
  EXPECT_NE(saved.find("\"lambda\": 0.1234567890123}"), std::string::npos) << saved;
  EXPECT_EQ(std::count(saved.begin(), saved.end(), '\n'), std::count(text.begin(), text.end(), '\n'));
}

}  // namespace
}  // namespace loom::editor::test
