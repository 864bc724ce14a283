// ImageWarp and WarpField run through the engine on generated checkerboards.
#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/testing.hpp"

namespace loom {
namespace {

json board() { return {{"type", "Checkerboard"}, {"inputs", {{"size", {256, 192}}, {"cells", 6}}}}; }

json warp_graph(json inputs) {
  inputs["image"] = {{"from", "board.image"}};
  return {{"loom", 1}, {"nodes", {{"board", board()}, {"warp", {{"type", "ImageWarp"}, {"inputs", inputs}}}}}};
}

const json kPairs = json::array({{60, 50, 80, 40}, {200, 50, 190, 70}, {144, 112, 150, 120}, {60, 150, 60, 150},
                                 {200, 150, 210, 140}});

TEST(ImageWarpNode, IdentityPairsGiveTheInputImage) {
  testing::Engine e;
  const Image& src = e.output<Image>({{"loom", 1}, {"nodes", {{"board", board()}}}}, "board.image");
  for (const char* method : {"idw", "rbf"})
    for (const char* mode : {"inverse", "forward"}) {
      const json pairs = json::array({{30, 30, 30, 30}, {200, 40, 200, 40}, {100, 150, 100, 150}});
      const Value v = e.value(warp_graph({{"pairs", pairs}, {"method", method}, {"mode", mode}}), "warp.image");
      EXPECT_LE(cv::norm(v.as<Image>().pixels, src.pixels, cv::NORM_INF), 1e-5) << method << " " << mode;
      EXPECT_EQ(v.as<Image>().encoding, Encoding::srgb);
    }
}

TEST(ImageWarpNode, InverseModeLeavesNoHolesAndSamplesPAtQ) {
  testing::Engine e;
  const Image& src = e.output<Image>({{"loom", 1}, {"nodes", {{"board", board()}}}}, "board.image");
  for (const char* method : {"idw", "rbf"}) {
    json g = warp_graph({{"pairs", kPairs}, {"method", method}, {"outside", "replicate"}});
    const Image& out = e.output<Image>(g, "warp.image");
    EXPECT_TRUE(cv::checkRange(out.pixels));
    EXPECT_EQ(cv::countNonZero(e.output<Image>(g, "warp.holes").pixels), 0);
    for (const auto& pq : kPairs) {
      const int qx = pq[2].get<int>(), qy = pq[3].get<int>(), px = pq[0].get<int>(), py = pq[1].get<int>();
      // p and q are pixel corners: compare the 2×2 means around them.
      cv::Scalar a = cv::mean(out.pixels(cv::Rect(qx - 1, qy - 1, 2, 2)));
      cv::Scalar b = cv::mean(src.pixels(cv::Rect(px - 1, py - 1, 2, 2)));
      EXPECT_LE(cv::norm(a - b), 1e-4) << method << " at q = " << qx << "," << qy;
    }
  }
}

TEST(ImageWarpNode, ForwardWithoutFillShowsWhiteLinesAndFillRemovesThem) {
  testing::Engine e;
  // A 1.4× magnification about the center, by RBF on affine pairs.
  json pairs = json::array();
  for (double x : {40.0, 128.0, 216.0})
    for (double y : {30.0, 96.0, 162.0}) pairs.push_back({x, y, 128 + 1.4 * (x - 128), 96 + 1.4 * (y - 96)});
  json g = warp_graph({{"pairs", pairs}, {"mode", "forward"}, {"fill_holes", false}});
  const int holes = cv::countNonZero(e.output<Image>(g, "warp.holes").pixels);
  EXPECT_GT(holes, 1000);
  g["nodes"]["warp"]["inputs"]["fill_holes"] = true;
  EXPECT_EQ(cv::countNonZero(e.output<Image>(g, "warp.holes").pixels), 0);
}

TEST(ImageWarpNode, DuplicatePairsWarnAndStillWarp) {
  testing::Engine e;
  json pairs = kPairs;
  pairs.push_back({60, 50, 90, 30});  // same p as pair 0, other q
  json g = warp_graph({{"pairs", pairs}, {"mode", "forward"}});
  const Graph graph = e.load(g);
  testing::Run r = e.run(graph, {"warp.image"});
  ASSERT_EQ(r.status("warp"), NodeStatus::ran);
  EXPECT_FALSE(r.warnings("warp").empty());
  EXPECT_TRUE(cv::checkRange(r.output<Image>("warp.image").pixels));
}

TEST(WarpFieldNode, DisplacementAtAControlPointIsQMinusP) {
  testing::Engine e;
  const json pairs = json::array({{100.5, 50.5, 110.5, 45.5}, {20.5, 80.5, 20.5, 80.5}, {60.5, 20.5, 70.5, 30.5}});
  for (const char* method : {"idw", "rbf"}) {
    json g = {{"loom", 1},
              {"nodes", {{"field", {{"type", "WarpField"},
                                    {"inputs", {{"size", {128, 96}}, {"pairs", pairs}, {"method", method}}}}}}}};
    const Image& d = e.output<Image>(g, "field.displacement");
    ASSERT_EQ(d.channels(), 2);
    const cv::Vec2f v = d.pixels.at<cv::Vec2f>(50, 100);
    EXPECT_NEAR(v[0], 10, 1e-4);
    EXPECT_NEAR(v[1], -5, 1e-4);
    const Image& overlay = e.output<Image>(g, "field.overlay");
    EXPECT_EQ(overlay.pixels.size(), cv::Size(128, 96));
    EXPECT_TRUE(cv::checkRange(overlay.pixels));
  }
}

}  // namespace
}  // namespace loom
