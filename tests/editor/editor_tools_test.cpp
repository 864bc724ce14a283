// The Poisson and MiniDraw tools driven by scripted mouse input: the region is
// drawn and dragged, figures are drawn, and the node's output is checked
// against the images it was made from.
#include <fstream>

#include "loom/image.hpp"
#include "ui_harness.hpp"

namespace loom::editor::test {
namespace {

namespace fs = std::filesystem;

cv::Vec3f at(const Image& image, int x, int y) { return image.pixels.at<cv::Vec3f>(y, x); }

json poisson_graph() {
  return json::parse(R"({"loom": 1, "nodes": {
    "target": {"type": "Checkerboard", "inputs": {"size": [512, 384], "cells": 4}, "ui": {"pos": [0, 0]}},
    "source": {"type": "Checkerboard", "inputs": {"size": [256, 256], "cells": 10,
               "color_a": [0.95, 0.6, 0.2], "color_b": [0.1, 0.55, 0.5]}, "ui": {"pos": [0, 200]}},
    "blend": {"type": "PoissonBlend", "inputs": {"source": {"from": "source.image"},
              "target": {"from": "target.image"}, "rectangle": [96, 96, 64, 64], "offset": [0, 0]},
              "ui": {"pos": [260, 60]}}}})");
}

TEST(EditorTools, PoissonRegionDragsOverTheTarget) {
  Harness h;
  h.app.open(write_graph(poisson_graph(), "poisson.json"));
  h.frame(2);
  auto& state = h.app.state();
  h.click(h.app.canvas().node_header(state, "blend"));
  ASSERT_TRUE(h.settle());
  const ImageView view = h.app.image_view();
  ASSERT_GT(view.scale, 0);
  const Image target = state.eval->output("target", "image").as<Image>();

  // Drag the region by (+200, +100) target pixels.
  h.drag(view.to_screen(128, 128), view.to_screen(328, 228), 0, 20);
  const json offset = h.app.document().literal("blend", "offset");
  EXPECT_NEAR(offset[0].get<double>(), 200, 1.0 / view.scale + 1);
  EXPECT_NEAR(offset[1].get<double>(), 100, 1.0 / view.scale + 1);
  ASSERT_TRUE(h.settle());
  const Image blended = state.eval->output("blend", "image").as<Image>();
  const int ox = offset[0].get<int>(), oy = offset[1].get<int>();
  // The old place is the target again; the new one is not.
  EXPECT_LT(cv::norm(at(blended, 128, 128) - at(target, 128, 128)), 1e-6);
  EXPECT_GT(cv::norm(at(blended, 128 + ox, 128 + oy) - at(target, 128 + ox, 128 + oy)), 0.05);
  // Outside the region, the target is untouched.
  EXPECT_LT(cv::norm(at(blended, 20, 370) - at(target, 20, 370)), 1e-6);
  // The whole drag is one undo step.
  h.jump({600, 790});  // away from menus and nodes
  h.key(GLFW_KEY_Z, true);
  EXPECT_EQ(h.app.document().literal("blend", "offset"), json({0, 0}));
  h.key(GLFW_KEY_Y, true);

  // Draw a triangle as the region on the source: it replaces the rectangle.
  h.app.poisson_tool().set_mode(PoissonTool::Mode::polygon);
  h.frame(2);
  const ImageView source_view = h.app.image_view();
  ASSERT_GT(source_view.scale, 0);
  h.click(source_view.to_screen(40, 40));
  h.click(source_view.to_screen(200, 40));
  h.click(source_view.to_screen(120, 200));
  h.click(source_view.to_screen(40, 40));  // closes
  const json polygon = h.app.document().literal("blend", "polygon");
  ASSERT_EQ(polygon.size(), 3u) << h.app.document().document()["nodes"]["blend"].dump();
  EXPECT_NEAR(polygon[1][0].get<double>(), 200, 1.0 / source_view.scale + 1);
  EXPECT_TRUE(h.app.document().literal("blend", "rectangle").is_null());
  EXPECT_EQ(h.app.poisson_tool().mode(), PoissonTool::Mode::move);
  ASSERT_TRUE(h.settle());
  EXPECT_TRUE(state.eval->result.ok()) << state.eval->result.nodes.at("blend").error;
  h.jump({600, 790});  // away from menus and nodes
  h.screenshot("poisson-tool");
}

TEST(EditorTools, DrawShapesAppendsFigures) {
  Harness h;
  const json graph = json::parse(R"({"loom": 1, "nodes": {
    "drawing": {"type": "DrawShapes", "inputs": {"size": [256, 256], "background": [1, 1, 1]}, "ui": {"pos": [0, 0]}}}})");
  h.app.open(write_graph(graph, "draw.json"));
  h.frame(2);
  auto& state = h.app.state();
  h.click(h.app.canvas().node_header(state, "drawing"));
  ASSERT_TRUE(h.settle());
  const ImageView view = h.app.image_view();
  ASSERT_GT(view.scale, 0);

  DrawTool& tool = h.app.draw_tool();
  tool.shape = DrawTool::Shape::rectangle;
  tool.fill = true;
  const float red[4] = {1, 0, 0, 1};
  std::copy(red, red + 4, tool.fill_color);
  h.drag(view.to_screen(40, 40), view.to_screen(120, 100));
  tool.shape = DrawTool::Shape::freehand;
  h.drag(view.to_screen(20, 200), view.to_screen(230, 230), 0, 10);
  const json figures = h.app.document().literal("drawing", "figures");
  ASSERT_EQ(figures.size(), 2u) << figures.dump();
  EXPECT_EQ(figures[0]["type"], "rectangle");
  const double slack = 1.0 / view.scale + 0.5;
  EXPECT_NEAR(figures[0]["min"][0].get<double>(), 40, slack);
  EXPECT_NEAR(figures[0]["max"][1].get<double>(), 100, slack);
  EXPECT_EQ(figures[1]["type"], "freehand");
  EXPECT_GE(figures[1]["points"].size(), 5u);
  ASSERT_TRUE(h.settle());
  const Image drawn = state.eval->output("drawing", "image").as<Image>();
  // Inside the rectangle: the fill; far from both figures: the background.
  EXPECT_LT(cv::norm(at(drawn, 80, 70) - cv::Vec3f(1, 0, 0)), 0.02) << at(drawn, 80, 70);
  EXPECT_LT(cv::norm(at(drawn, 200, 60) - cv::Vec3f(1, 1, 1)), 0.02);
  h.jump({600, 790});  // away from menus and nodes
  h.screenshot("draw-tool");
  // Each figure is one undo step.
  h.key(GLFW_KEY_Z, true);
  EXPECT_EQ(h.app.document().literal("drawing", "figures").size(), 1u);
}

}  // namespace
}  // namespace loom::editor::test

namespace loom::editor::test {
namespace {

TEST(EditorViewers, MeshIsDrawnInTheEditorsContext) {
  Harness h;
  const json graph = json::parse(R"({"loom": 1, "nodes": {
    "sphere": {"type": "UVSphere", "inputs": {"rings": 24, "segments": 48}, "ui": {"pos": [0, 0]}}}})");
  h.app.open(write_graph(graph, "sphere.json"));
  h.frame(2);
  h.click(h.app.canvas().node_header(h.app.state(), "sphere"));
  ASSERT_TRUE(h.settle());
  h.jump({600, 790});
  const Rgba8Image shot = h.screenshot("mesh-viewer");
  const ImVec2 lo = h.app.mesh_viewer().shown_min(), hi = h.app.mesh_viewer().shown_max();
  ASSERT_GT(hi.x - lo.x, 100);
  ASSERT_GT(hi.y - lo.y, 100);
  auto pixel = [&](float x, float y) { return shot.at(int(x), int(y)); };
  auto background = [&](const std::uint8_t* p) {
    return std::abs(p[0] - 41) <= 3 && std::abs(p[1] - 41) <= 3 && std::abs(p[2] - 46) <= 3;
  };
  // The sphere covers the middle of the view and leaves the corners empty.
  EXPECT_FALSE(background(pixel((lo.x + hi.x) / 2, (lo.y + hi.y) / 2)));
  EXPECT_TRUE(background(pixel(lo.x + 3, lo.y + 3)));
  EXPECT_TRUE(background(pixel(hi.x - 3, hi.y - 3)));
  // Facing the headlight, the middle is the brightest shade (near the base colour).
  EXPECT_GT(pixel((lo.x + hi.x) / 2, (lo.y + hi.y) / 2)[0], 150);
}

}  // namespace
}  // namespace loom::editor::test
