// The editor's model pieces without a window: files written back in the
// layout they were read in, issues placed by their decoded JSON pointer,
// widgets chosen from declarations, the node search's ranking, free spots
// for new nodes, and links read by the engine's parser.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "controller/evaluation_controller.hpp"
#include "loom/builtin_types.hpp"
#include "loom/image.hpp"
#include "loom/testing.hpp"
#include "model/auto_layout.hpp"
#include "model/graph_document.hpp"
#include "model/input_widget.hpp"
#include "model/json_layout.hpp"
#include "model/node_issue.hpp"
#include "model/node_search.hpp"
#include "test_files.hpp"

namespace loom::editor {
namespace {

namespace fs = std::filesystem;

using test::read_text;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// The reference is the file itself: each example graph, parsed and written
// back in its own layout, is the same bytes (hand-written one-line nodes,
// one-number-per-line dumps, "100000.0", "×" and all).
TEST(JsonLayout, EveryExampleGraphIsWrittenBackByteForByte) {
  int files = 0;
  for (const auto& e : fs::directory_iterator(fs::path(LOOM_SOURCE_DIR) / "graphs")) {
    if (e.path().extension() != ".json") continue;
    const std::string text = read_text(e.path());
    const json doc = json::parse(text);
    EXPECT_EQ(write_json(doc, scan_json_layout(text)), text) << e.path();
    ++files;
  }
  EXPECT_GT(files, 20);
}

TEST(JsonLayout, KeyOrderTokensAndOneLineContainersAreKept) {
  const std::string text =
      "{\n"
      "    \"nodes\": {\n"
      "        \"b\": {\"inputs\": {\"k\": 1e5, \"size\": [4, 4]}, \"type\": \"X\"},\n"
      "        \"a\": {\n"
      "            \"type\": \"Y\",\n"
      "            \"inputs\": {\"value\": 0.5}\n"
      "        }\n"
      "    },\n"
      "    \"loom\": 1\n"
      "}\n";
  json doc = json::parse(text);
  const JsonLayout layout = scan_json_layout(text);
  EXPECT_EQ(layout.indent, "    ");
  EXPECT_EQ(write_json(doc, layout), text);
  // A one-value edit changes that value's line only; new keys go after the
  // file's own; a new short array is written on one line.
  doc["nodes"]["a"]["inputs"]["value"] = 0.25;
  std::vector<std::string> before = lines(text), after = lines(write_json(doc, layout));
  ASSERT_EQ(before.size(), after.size());
  int changed = 0;
  for (std::size_t i = 0; i < before.size(); ++i) changed += before[i] != after[i];
  EXPECT_EQ(changed, 1);
  EXPECT_EQ(after[5], "            \"inputs\": {\"value\": 0.25}");
  doc["nodes"]["a"]["ui"] = {{"pos", {40.0, 120.5}}};
  doc["nodes"]["b"]["inputs"]["k"] = 2e5;
  const std::string grown = write_json(doc, layout);
  EXPECT_NE(grown.find("\"b\": {\"inputs\": {\"k\": 200000.0, \"size\": [4, 4]}, \"type\": \"X\"}"), std::string::npos)
      << grown;
  EXPECT_NE(grown.find("\"inputs\": {\"value\": 0.25},\n            \"ui\": {\"pos\": [40.0, 120.5]}"), std::string::npos)
      << grown;
  EXPECT_EQ(json::parse(grown), doc);
}

TEST(JsonLayout, ANewGraphHasANodeALineAndShortArraysOnOneLine) {
  json doc = {{"loom", 1}, {"nodes", json::object()}};
  doc["nodes"]["board"] = {{"ui", {{"pos", {40.0, 40.0}}}}, {"type", "Checkerboard"}, {"inputs", {{"size", {64, 64}}}}};
  std::vector<double> many(60, 0.125);
  doc["nodes"]["long"] = {{"type", "T"}, {"inputs", {{"values", many}}}};
  const std::string text = write_json(doc, {});
  EXPECT_NE(text.find("\n    \"board\": {\"type\": \"Checkerboard\", \"inputs\": {\"size\": [64, 64]}, "
                      "\"ui\": {\"pos\": [40.0, 40.0]}}"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.rfind("{\n  \"loom\": 1,\n  \"nodes\": {\n", 0), 0u) << text;
  EXPECT_GT(lines(text).size(), 60u);  // the long list: one value a line
  EXPECT_EQ(json::parse(text), doc);
}

struct ModelFixture : ::testing::Test {
  testing::Engine engine;
  void SetUp() override { engine.load_all_plugins(); }
};
using EditorModel = ModelFixture;

// The file the issue reported: saving after a one-value edit diffs in one
// line, and a double keeps every digit.
TEST_F(EditorModel, SavedFileDiffsInOneLineAfterOneEdit) {
  const fs::path file = test::temp_dir() / "hand.json";
  const std::string text =
      "{\n"
      "  \"loom\": 1,\n"
      "  \"description\": \"written by hand\",\n"
      "  \"nodes\": {\n"
      "    \"board\": {\"type\": \"Checkerboard\", \"inputs\": {\"size\": [64, 64], \"cells\": 4}, \"ui\": {\"pos\": [40, 40]}},\n"
      "    \"warp\": {\"type\": \"ImageWarp\", \"inputs\": {\"image\": {\"from\": \"board.image\"}, \"idw_power\": 2},\n"
      "             \"ui\": {\"pos\": [300, 40]}}\n"
      "  }\n"
      "}\n";
  std::ofstream(file) << text;
  GraphDocument doc(engine.registry());
  doc.load(file);
  doc.save(file);
  EXPECT_EQ(read_text(file), text);  // nothing edited: the same bytes
  doc.set_input("warp", "idw_power", 0.1234567890123456);
  doc.save(file);
  const std::vector<std::string> before = lines(text), after = lines(read_text(file));
  ASSERT_EQ(before.size(), after.size());
  for (std::size_t i = 0; i < before.size(); ++i)
    if (i != 5) {
      EXPECT_EQ(before[i], after[i]) << i;
    }
  EXPECT_NE(after[5].find("\"idw_power\": 0.1234567890123456}"), std::string::npos) << after[5];
  GraphDocument again(engine.registry());
  again.load(file);
  EXPECT_EQ(again.literal("warp", "idw_power").get<double>(), 0.1234567890123456);
}

TEST(NodeIssue, PointersAreDecodedWithTheirEscapes) {
  EXPECT_EQ(pointer_tokens("/nodes/a~1b/inputs/c~0d~01/0"),
            (std::vector<std::string>{"nodes", "a/b", "inputs", "c~d~1", "0"}));
  const NodeIssue on_input = locate_issue({"/nodes/grp~1warp/inputs/method", "bad"});
  EXPECT_EQ(on_input.node, "grp/warp");
  EXPECT_EQ(on_input.input, "method");
  const NodeIssue on_node = locate_issue({"/nodes/x~0y/type", "unknown"});
  EXPECT_EQ(on_node.node, "x~y");
  EXPECT_EQ(on_node.input, "");
  EXPECT_EQ(locate_issue({"/time/fps", "negative"}).node, "");
}

// End to end: the engine's own pointer for a node whose id holds a '/'.
TEST_F(EditorModel, AnIssueOfANodeWithASlashInItsIdLandsOnThatNode) {
  EvaluationController controller(engine.registry(), 1);
  EvalRequest r;
  r.document = {{"loom", 1},
                {"nodes",
                 {{"group/board", {{"type", "Checkerboard"}}},
                  {"group/warp",
                   {{"type", "ImageWarp"}, {"inputs", {{"image", {{"from", "group/board.image"}}}, {"method", "cubic"}}}}}}}};
  r.file = test::temp_dir() / "slash.json";
  controller.submit(r);
  controller.wait_idle();
  const auto& issues = controller.latest()->issues;
  ASSERT_FALSE(issues.empty());
  EXPECT_EQ(issues[0].node, "group/warp") << issues[0].pointer;
  EXPECT_EQ(issues[0].input, "method");
}

TEST(InputWidget, ChosenFromTheDeclaration) {
  auto spec = [](const TypeInfo& type, std::optional<double> lo = {}, std::optional<double> hi = {},
                 InputRole role = InputRole::value) {
    InputSpec s;
    s.type = &type;
    s.min = lo;
    s.max = hi;
    s.role = role;
    return s;
  };
  EXPECT_EQ(widget_for(spec(type_of<double>(), 0.0, 1.0)), InputWidget::number_slider);
  EXPECT_EQ(widget_for(spec(type_of<double>(), 0.0)), InputWidget::number_drag);
  EXPECT_EQ(widget_for(spec(type_of<double>(), 0.0, 1e6)), InputWidget::number_drag);
  EXPECT_EQ(widget_for(spec(type_of<int>(), 1.0, 64.0)), InputWidget::int_slider);
  EXPECT_EQ(widget_for(spec(type_of<int>())), InputWidget::int_drag);
  EXPECT_EQ(widget_for(spec(type_of<bool>())), InputWidget::checkbox);
  EXPECT_EQ(widget_for(spec(enum_type())), InputWidget::choice);
  EXPECT_EQ(widget_for(spec(type_of<std::string>())), InputWidget::text);
  EXPECT_EQ(widget_for(spec(type_of<std::string>(), {}, {}, InputRole::input_file)), InputWidget::file);
  EXPECT_EQ(widget_for(spec(type_of<std::string>(), {}, {}, InputRole::output_file)), InputWidget::file);
  EXPECT_EQ(widget_for(spec(type_of<Color>())), InputWidget::color);
  EXPECT_EQ(widget_for(spec(type_of<Vec2>())), InputWidget::number_vector);
  EXPECT_EQ(vector_size(spec(type_of<Vec3>())), 3);
  EXPECT_EQ(widget_for(spec(type_of<Vec3i>())), InputWidget::int_vector);
  EXPECT_EQ(widget_for(spec(type_of<std::vector<Vec2>>())), InputWidget::json_text);
  EXPECT_EQ(widget_for(spec(type_of<Image>())), InputWidget::link_only);
}

std::vector<std::string> names(const std::vector<const NodeType*>& types) {
  std::vector<std::string> out;
  for (const NodeType* t : types) out.push_back(t->spec.name);
  return out;
}
std::size_t rank_of(const std::vector<std::string>& list, const std::string& name) {
  return std::size_t(std::find(list.begin(), list.end(), name) - list.begin());
}

TEST_F(EditorModel, SearchRanksNamesBeforeDescriptions) {
  const auto smooth = names(search_node_types(engine.registry(), "smooth"));
  ASSERT_FALSE(smooth.empty());
  EXPECT_EQ(smooth[0], "SmoothMesh");
  ASSERT_LT(rank_of(smooth, "HeightMap"), smooth.size()) << "HeightMap's description mentions smooth bumps";
  EXPECT_LT(rank_of(smooth, "SmoothMesh"), rank_of(smooth, "HeightMap"));
  EXPECT_EQ(names(search_node_types(engine.registry(), "math"))[0], "Math");             // exact
  EXPECT_EQ(names(search_node_types(engine.registry(), "save image"))[0], "SaveImage");  // spaces ignored
  const auto mesh = names(search_node_types(engine.registry(), "mesh"));
  EXPECT_LT(rank_of(mesh, "SmoothMesh"), rank_of(mesh, "Render"));  // a word of a name before a description
  const auto emit = names(search_node_types(engine.registry(), "emit"));
  EXPECT_EQ(emit[0].rfind("MPMEmit", 0), 0u);
  EXPECT_EQ(match_node_type(engine.registry().find("SmoothMesh")->spec, "Mesh"), SearchMatch::word);
  EXPECT_EQ(search_node_types(engine.registry(), "").size(), engine.registry().all().size());
  EXPECT_TRUE(search_node_types(engine.registry(), "zzzz-nothing").empty());
}

TEST(FreeSpot, TheNearestPlaceThatOverlapsNoNode) {
  const std::vector<CanvasRect> taken = {{0, 0, 220, 200}, {240, 0, 220, 200}};
  EXPECT_EQ(free_spot(taken, {600, 600}, 220, 150).x, 600);  // free already
  const CanvasPoint p = free_spot(taken, {20, 20}, 220, 150);
  for (const CanvasRect& r : taken)
    EXPECT_FALSE(p.x < r.x + r.width && r.x < p.x + 220 && p.y < r.y + r.height && r.y < p.y + 150)
        << p.x << ", " << p.y;
  EXPECT_LT(std::hypot(p.x - 20, p.y - 20), 260);  // below the first node, not far away
}

// Two boxes of the level shown that overlap, as "a / b", or "".
std::string overlapping(const GraphDocument& doc) {
  const auto ids = doc.node_ids();
  std::vector<CanvasRect> boxes;
  for (const auto& id : ids)
    boxes.push_back({doc.position(id).x, doc.position(id).y, kNodeWidth, node_height(doc.node_type(id))});
  for (std::size_t i = 0; i < ids.size(); ++i)
    for (std::size_t j = i + 1; j < ids.size(); ++j) {
      const CanvasRect &a = boxes[i], &b = boxes[j];
      if (a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height)
        return ids[i] + " / " + ids[j];
    }
  return {};
}

json without_positions(json doc) {
  auto strip = [](json& level) {
    if (level.is_object() && level.contains("nodes"))
      for (auto& [id, node] : level["nodes"].items()) node.erase("ui");
  };
  strip(doc);
  if (doc.contains("groups"))
    for (auto& [name, group] : doc["groups"].items()) strip(group);
  return doc;
}

// Issue 42, item 3: the automatic layout puts no node on another, in every
// example graph and library group, at the top and inside each group or
// Repeat body (positions dropped, as in a hand-written file), each box as tall
// as the canvas draws it (group nodes and Repeat nodes with their pins); and
// the files as shipped open without overlaps either.
TEST_F(EditorModel, TheAutomaticLayoutNeverOverlapsNodes) {
  std::vector<fs::path> files;
  for (const fs::path& folder : {fs::path(LOOM_SOURCE_DIR) / "graphs", fs::path(LOOM_SOURCE_DIR) / "graphs" / "lib"})
    for (const auto& e : fs::directory_iterator(folder))
      if (e.path().extension() == ".json") files.push_back(e.path());
  ASSERT_GT(files.size(), 20u);
  int levels = 0;
  for (const fs::path& file : files) {
    const json shipped = json::parse(read_text(file));
    for (const json& doc_json : {without_positions(shipped), shipped}) {
      GraphDocument doc(engine.registry());
      doc.load_json(doc_json, file);
      EXPECT_EQ(overlapping(doc), "") << file;
      ++levels;
      for (const auto& id : doc.node_ids()) {
        if (!doc.is_group_node(id) || !doc.enter(id)) continue;
        EXPECT_EQ(overlapping(doc), "") << file << " inside " << id;
        ++levels;
        doc.leave(0);
      }
    }
  }
  EXPECT_GT(levels, 2 * int(files.size()));
}

TEST_F(EditorModel, LinksAreReadByTheEnginesParser) {
  GraphDocument doc(engine.registry());
  doc.load_json(json::parse(R"({"loom": 1, "nodes": {
    "a": {"type": "Math"}, "b": {"type": "Math", "inputs": {"a": {"from": "a.result"}}}}})"));
  doc.set_input("b", "b", {{"from", "a."}});
  ASSERT_TRUE(doc.link("b", "a"));
  EXPECT_EQ(doc.link("b", "a")->output, "result");
  EXPECT_FALSE(doc.link("b", "b")) << "an empty output name is no link";
}

}  // namespace
}  // namespace loom::editor
