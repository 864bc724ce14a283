// The shading nodes through the engine, with the scene and generate plugins.
#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/testing.hpp"

namespace loom {
namespace {

TEST(ShadingNodes, RenderOfAGeneratedSceneIsFiniteAndSized) {
  testing::Engine engine;
  const json g = {{"loom", 1},
                  {"nodes",
                   {{"ball", {{"type", "UVSphere"}, {"inputs", json::object()}}},
                    {"obj", {{"type", "Object"}, {"inputs", {{"mesh", {{"from", "ball.mesh"}}}}}}},
                    {"sun", {{"type", "Light"}, {"inputs", {{"kind", "directional"}, {"direction", {0, -1, -1}}}}}},
                    {"scene", {{"type", "MergeScenes"}, {"inputs", {{"a", {{"from", "obj.scene"}}}, {"b", {{"from", "sun.scene"}}}}}}},
                    {"render", {{"type", "Render"}, {"inputs", {{"scene", {{"from", "scene.scene"}}}, {"width", 96}, {"height", 64}}}}}}}};
  const Image& image = engine.output<Image>(g, "render.image");
  EXPECT_EQ(image.width(), 96);
  EXPECT_EQ(image.height(), 64);
  EXPECT_EQ(image.channels(), 3);
  EXPECT_EQ(image.encoding, Encoding::linear);
  EXPECT_NO_THROW(require_finite(image, "render"));
  EXPECT_GT(cv::norm(image.pixels, cv::NORM_INF), 0.1);  // the lit sphere is there
  const Image& depth = engine.output<Image>(g, "render.depth");
  EXPECT_EQ(depth.width(), 96);
  EXPECT_EQ(depth.channels(), 1);
  // Twice in one session: the context kept in scratch is reused.
  EXPECT_EQ(engine.output<Image>(g, "render.normal").channels(), 3);
}

TEST(ShadingNodes, DenoisingNeedsUVs) {
  testing::Engine engine;
  const json g = {{"loom", 1},
                  {"nodes",
                   {{"ball", {{"type", "UVSphere"}, {"inputs", json::object()}}},
                    {"map", {{"type", "DisplacementFromNoise"}, {"inputs", {{"mesh", {{"from", "ball.mesh"}}}}}}}}}};
  testing::Run r = engine.run(g, {"map.image"});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error("map").find("UVs"), std::string::npos) << r.error("map");
}

TEST(ShadingNodes, HeightToNormalMapOfAFlatFieldPointsUp) {
  testing::Engine engine;
  const json g = {{"loom", 1},
                  {"nodes",
                   {{"h", {{"type", "HeightMap"}, {"inputs", {{"pattern", "bumps"}, {"size", {64, 64}}, {"rows", 1}, {"columns", 1}}}}},
                    {"n", {{"type", "HeightToNormalMap"}, {"inputs", {{"height", {{"from", "h.image"}}}, {"strength", 0.0}}}}}}}};
  const Image& n = engine.output<Image>(g, "n.image");
  const cv::Vec3f c = n.pixels.at<cv::Vec3f>(10, 20);
  EXPECT_FLOAT_EQ(c[0], 0.5f);
  EXPECT_FLOAT_EQ(c[1], 0.5f);
  EXPECT_FLOAT_EQ(c[2], 1.0f);
}

}  // namespace
}  // namespace loom
