// DrawShapes and PolygonMask through the engine.
#include <cmath>

#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/testing.hpp"

namespace loom {
namespace {

json draw_graph(json figures, json extra = json::object()) {
  json inputs = {{"size", {64, 48}}, {"background", "#ffffff"}, {"figures", std::move(figures)}};
  inputs.update(extra);
  return {{"loom", 1}, {"nodes", {{"draw", {{"type", "DrawShapes"}, {"inputs", inputs}}}}}};
}

TEST(DrawShapesNode, FilledRectangleIsExactInsideAndLeavesTheRestAlone) {
  testing::Engine e;
  const json figures = json::parse(R"([{"type": "rectangle", "min": [10, 8], "max": [30, 20],
                                        "fill": [1, 0, 0], "width": 0}])");
  const Image& img = e.output<Image>(draw_graph(figures), "draw.image");
  EXPECT_EQ(img.encoding, Encoding::srgb);
  EXPECT_EQ(img.channels(), 3);
  EXPECT_EQ(img.pixels.at<cv::Vec3f>(10, 20), cv::Vec3f(1, 0, 0));
  EXPECT_EQ(img.pixels.at<cv::Vec3f>(8, 10), cv::Vec3f(1, 0, 0));    // first covered pixel
  EXPECT_EQ(img.pixels.at<cv::Vec3f>(20, 20), cv::Vec3f(1, 1, 1));   // just below: untouched
  EXPECT_EQ(img.pixels.at<cv::Vec3f>(5, 5), cv::Vec3f(1, 1, 1));
  // Red covers exactly the 20 × 12 pixels.
  cv::Mat green;
  cv::extractChannel(img.pixels, green, 1);
  EXPECT_NEAR(cv::sum(1.0 - green)[0], 20 * 12, 1e-3);
}

TEST(DrawShapesNode, EllipseFillAreaAndEvenOddHole) {
  testing::Engine e;
  const json figures = json::parse(R"([{"type": "ellipse", "center": [32, 24], "axes": [20, 12], "angle": 30,
                                        "fill": [0, 0, 0], "width": 0}])");
  const Image& img = e.output<Image>(draw_graph(figures), "draw.image");
  cv::Mat red;
  cv::extractChannel(img.pixels, red, 0);
  EXPECT_NEAR(cv::sum(1.0 - red)[0], M_PI * 20 * 12, 0.5);

  const json star = json::parse(R"([{"type": "polygon", "fill_rule": "evenodd", "fill": [0, 0, 0], "width": 0,
      "points": [[32, 2], [45, 42], [11, 17], [53, 17], [19, 42]]}])");
  const Image& s = e.output<Image>(draw_graph(star), "draw.image");
  EXPECT_EQ(s.pixels.at<cv::Vec3f>(26, 32), cv::Vec3f(1, 1, 1));  // the inner pentagon stays background
  EXPECT_EQ(s.pixels.at<cv::Vec3f>(6, 32), cv::Vec3f(0, 0, 0));
}

TEST(DrawShapesNode, StrokesAreAntialiasedOnAnInputImage) {
  testing::Engine e;
  json g = draw_graph(json::parse(R"([{"type": "line", "from": [4, 10.3], "to": [60, 30.7], "stroke": [0, 0, 0], "width": 2},
                                      {"type": "arrow", "from": [5, 40], "to": [50, 40], "stroke": "#0000ff", "width": 3},
                                      {"type": "freehand", "points": [[2, 2], [10, 5], [20, 3]], "width": 1}])"));
  g["nodes"]["board"] = {{"type", "Checkerboard"}, {"inputs", {{"size", {64, 48}}, {"cells", 2},
                                                              {"color_a", {1, 1, 1}}, {"color_b", {1, 1, 1}}}}};
  g["nodes"]["draw"]["inputs"]["image"] = {{"from", "board.image"}};
  const Image& img = e.output<Image>(g, "draw.image");
  EXPECT_TRUE(cv::checkRange(img.pixels));
  cv::Mat red;
  cv::extractChannel(img.pixels, red, 0);
  const int partial = cv::countNonZero((red > 0.05f) & (red < 0.95f));
  EXPECT_GT(partial, 20);  // anti-aliased edge pixels
  EXPECT_LT(img.pixels.at<cv::Vec3f>(40, 30)[0], 0.1f);  // the arrow's shaft is blue
  EXPECT_GT(img.pixels.at<cv::Vec3f>(40, 30)[2], 0.9f);
}

TEST(DrawShapesNode, BadFigureFailsWithItsIndexAndKey) {
  testing::Engine e;
  const json g = draw_graph(json::parse(R"([{"type": "line", "from": [0, 0], "to": [1, 1]},
                                             {"type": "rectangle", "min": [0, 0]}])"));
  testing::Run r = e.run(g, {"draw.image"});
  ASSERT_EQ(r.status("draw"), NodeStatus::failed);
  EXPECT_NE(r.error("draw").find("figure 1 (rectangle): key \"max\" is missing"), std::string::npos) << r.error("draw");
}

TEST(PolygonMaskNode, MaskIsOneChannelLinearWithTheArea) {
  testing::Engine e;
  const json g = {{"loom", 1},
                  {"nodes", {{"mask", {{"type", "PolygonMask"},
                                       {"inputs", {{"size", {100, 80}},
                                                   {"points", {{10.5, 10}, {90, 20.25}, {60, 70.75}}}}}}}}}};
  const Image& m = e.output<Image>(g, "mask.mask");
  EXPECT_EQ(m.channels(), 1);
  EXPECT_EQ(m.encoding, Encoding::linear);
  const double area = std::abs((90 - 10.5) * (70.75 - 10) - (60 - 10.5) * (20.25 - 10)) / 2;
  EXPECT_NEAR(cv::sum(m.pixels)[0], area, 1e-3 * area);

  json bad = g;
  bad["nodes"]["mask"]["inputs"]["points"] = {{1, 1}, {2, 2}};
  testing::Run r = e.run(bad, {"mask.mask"});
  EXPECT_EQ(r.status("mask"), NodeStatus::failed);
  EXPECT_NE(r.error("mask").find("at least 3 vertices"), std::string::npos);
}

}  // namespace
}  // namespace loom
