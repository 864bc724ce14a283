// CornellBox, NightSky and PathTrace through the engine.
#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/scene.hpp"
#include "loom/testing.hpp"
#include "test_scenes.hpp"

namespace {

loom::json cornell_graph(int spp, const loom::json& extra = loom::json::object()) {
  loom::json pt = {{"type", "PathTrace"},
                   {"inputs", {{"scene", {{"from", "box.scene"}}}, {"size", {48, 32}}, {"spp", spp}}}};
  for (auto it = extra.begin(); it != extra.end(); ++it) pt["inputs"][it.key()] = it.value();
  return {{"loom", 1},
          {"seed", 3},
          {"nodes", {{"box", {{"type", "CornellBox"}, {"inputs", loom::json::object()}}}, {"pt", pt}}}};
}

TEST(PathTraceNodes, CornellBoxRendersAndReusesTheBvh) {
  loom::testing::Engine engine;
  auto r = engine.run(cornell_graph(4), {"pt"});
  ASSERT_TRUE(r.ok()) << r.error("pt");
  const auto& image = r.result().outputs.at("pt")[0].as<loom::Image>();
  EXPECT_EQ(image.width(), 48);
  EXPECT_EQ(image.height(), 32);
  EXPECT_EQ(loom::pathtrace::test::count_nonfinite(image.pixels), 0);
  const cv::Scalar mean = cv::mean(image.pixels);
  EXPECT_GT(mean[0], mean[2]);  // the light is warm: 17 12 4
  const auto stats = r.result().outputs.at("pt")[6].as<loom::json>();
  EXPECT_FALSE(stats["bvh_reused"].get<bool>());
  EXPECT_EQ(stats["emissive_triangles"].get<int>(), 2);
  EXPECT_EQ(stats["triangles"].get<int>(), 32);
  // Another sample count and strategy: same geometry, so the BVH is reused.
  r = engine.run(cornell_graph(2, {{"strategy", "nee"}}), {"pt"});
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r.result().outputs.at("pt")[6].as<loom::json>()["bvh_reused"].get<bool>());
  EXPECT_DOUBLE_EQ(r.result().outputs.at("pt")[5].as<double>(), 2.0);
}

TEST(PathTraceNodes, AdaptiveSamplingStopsEarlyWhereTheImageIsSmooth) {
  loom::testing::Engine engine;
  const auto doc = cornell_graph(256, {{"adaptive_threshold", 0.05}, {"adaptive_min_spp", 16}});
  const double spp = engine.output<double>(doc, "pt.spp");
  EXPECT_GE(spp, 16);
  EXPECT_LT(spp, 200);
  const auto& samples = engine.output<loom::Image>(doc, "pt.samples");
  double lo, hi;
  cv::minMaxLoc(samples.pixels, &lo, &hi);
  EXPECT_GE(lo, 16);
  EXPECT_LE(hi, 256);
}

TEST(PathTraceNodes, AovsDescribeTheFirstHit) {
  loom::testing::Engine engine;
  const auto doc = cornell_graph(2);
  const auto& normal = engine.output<loom::Image>(doc, "pt.normal");
  const auto& depth = engine.output<loom::Image>(doc, "pt.depth");
  const auto& albedo = engine.output<loom::Image>(doc, "pt.albedo");
  // Row 12, middle column: just above the tall block, the back wall: normal
  // -z, 1359.2 mm away along z (800 to the box's front + 559.2 deep) at a
  // slope of 0.078 (1363 mm along the ray), white albedo 0.725 0.71 0.68.
  const cv::Vec3f n = normal.pixels.at<cv::Vec3f>(12, 24);
  EXPECT_NEAR(n[2], -1, 1e-3);
  EXPECT_NEAR(depth.pixels.at<float>(12, 24), 1363.4, 2);
  EXPECT_NEAR(albedo.pixels.at<cv::Vec3f>(12, 24)[0], 0.725, 1e-4);
  // The ceiling at the top: normal -y.
  EXPECT_NEAR(normal.pixels.at<cv::Vec3f>(1, 24)[1], -1, 1e-3);
}

TEST(PathTraceNodes, NightSkyIsAFiniteLatLongMap) {
  loom::testing::Engine engine;
  const loom::json doc = {{"loom", 1},
                          {"nodes", {{"sky", {{"type", "NightSky"}, {"inputs", {{"size", {64, 32}}}}}}}}};
  const auto& sky = engine.output<loom::Image>(doc, "sky.image");
  EXPECT_EQ(sky.width(), 64);
  EXPECT_EQ(loom::pathtrace::test::count_nonfinite(sky.pixels), 0);
  double hi;
  cv::minMaxLoc(sky.pixels.reshape(1), nullptr, &hi);
  EXPECT_NEAR(hi, 300, 1e-3);  // the moon
}

TEST(PathTraceNodes, ActionableErrors) {
  loom::testing::Engine engine;
  EXPECT_THROW(engine.load(cornell_graph(0)), loom::Error);  // spp below its range
  auto doc = cornell_graph(1);
  doc["nodes"]["box"]["inputs"]["light"] = {-1, 0, 0};
  EXPECT_THROW(engine.value(doc, "pt.image"), loom::Error);
}

}  // namespace
