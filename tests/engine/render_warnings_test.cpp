// Silent wrong pictures made loud: a scene that nothing lights, and a texture
// on a mesh without UVs, are warnings from both renderers (Render and
// PathTrace), on stderr and in the profile. Each warning is checked against
// the picture itself: the unlit image is black, the map without UVs shows as
// one flat color, and neither warning appears once the scene is fixed.
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "runner_helpers.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;
using test::from;
using test::read_json;

// A unit quad facing +z, with or without texture coordinates.
void write_quad(const fs::path& file, bool uvs) {
  std::ofstream obj(file);
  obj << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n";
  if (uvs) obj << "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  else obj << "f 1 2 3\nf 1 3 4\n";
}

// A checker-textured quad seen from +z, rendered by both renderers; `light`
// adds a light at the camera.
json scene_graph(const std::string& mesh_file, bool light) {
  json nodes = {
      {"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {64, 64}}, {"cells", 4}}}}},
      {"quad", {{"type", "LoadMesh"}, {"inputs", {{"path", mesh_file}}}}},
      {"fabric", {{"type", "Material"}, {"inputs", {{"base_color", {1, 1, 1}}, {"base_color_map", from("board.image")}, {"specular", 0}}}}},
      {"object", {{"type", "Object"}, {"inputs", {{"mesh", from("quad.mesh")}, {"material", from("fabric.material")}, {"name", "quad"}}}}},
      {"camera", {{"type", "Camera"}, {"inputs", {{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}, {"fov_degrees", 40}}}}},
      {"scene", {{"type", "MergeScenes"}, {"inputs", {{"a", from("object.scene")}, {"b", from("camera.scene")}}}}},
      {"render", {{"type", "Render"}, {"inputs", {{"scene", from("scene.scene")}, {"width", 64}, {"height", 64}, {"samples", 1}, {"shadows", "off"}, {"extra_images", false}}}}},
      {"trace", {{"type", "PathTrace"}, {"inputs", {{"scene", from("scene.scene")}, {"size", {32, 32}}, {"spp", 4}, {"max_depth", 1}}}}},
      {"save_render", {{"type", "SaveImage"}, {"inputs", {{"image", from("render.image")}, {"path", "render.png"}}}}},
      {"save_trace", {{"type", "SaveImage"}, {"inputs", {{"image", from("trace.image")}, {"path", "trace.png"}}}}}};
  if (light) {
    nodes["lamp"] = {{"type", "Light"}, {"inputs", {{"kind", "directional"}, {"direction", {0.3, -0.3, -1}}, {"intensity", 2}}}};
    nodes["scene"]["inputs"]["c"] = from("lamp.scene");
  }
  return {{"loom", 1}, {"nodes", nodes}};
}

struct Outcome {
  int code = -1;
  std::string output;
  json profile;
  cv::Mat render, trace;  // 8-bit, as saved
};

Outcome run(const fs::path& dir, bool uvs, bool light) {
  write_quad(dir / "quad.obj", uvs);
  std::ofstream(dir / "g.json") << scene_graph("quad.obj", light).dump(2);
  Outcome o;
  o.code = test::run_loom("run " + (dir / "g.json").string() + " --no-cache --out " + (dir / "out").string() +
                              " --profile " + (dir / "p.json").string(),
                          &o.output);
  if (o.code != 0) return o;
  o.profile = read_json(dir / "p.json");
  o.render = cv::imread((dir / "out" / "render.png").string(), cv::IMREAD_GRAYSCALE);
  o.trace = cv::imread((dir / "out" / "trace.png").string(), cv::IMREAD_GRAYSCALE);
  return o;
}

const char* kUnlit = "nothing lights the scene";
const char* kNoUvs = "object 'quad': its mesh has no UVs, so its material's base-color map cannot be placed on it";

bool warned(const Outcome& o, const std::string& node, const std::string& text) {
  bool in_profile = false;
  for (const auto& w : o.profile["nodes"][node].value("warnings", json::array()))
    in_profile = in_profile || w.get<std::string>().find(text) != std::string::npos;
  const bool on_stderr = o.output.find("warning: [" + node + "] " + text) != std::string::npos;
  EXPECT_EQ(in_profile, on_stderr) << node << ": " << text << "\n" << o.output;
  return in_profile && on_stderr;
}

double max_of(const cv::Mat& m) {
  double lo = 0, hi = 0;
  cv::minMaxLoc(m, &lo, &hi);
  return hi;
}

// Spread of the pixels inside the quad (the middle half of the image).
double spread_on_quad(const cv::Mat& m) {
  cv::Scalar mean, stddev;
  cv::meanStdDev(m(cv::Rect(m.cols / 4, m.rows / 4, m.cols / 2, m.rows / 2)), mean, stddev);
  return stddev[0];
}

TEST(RenderWarnings, AnUnlitSceneIsBlackAndBothRenderersSaySo) {
  const Outcome o = run(test::temp_dir(), true, false);
  ASSERT_EQ(o.code, 0) << o.output;
  EXPECT_TRUE(warned(o, "render", kUnlit));
  EXPECT_TRUE(warned(o, "trace", kUnlit));
  EXPECT_EQ(max_of(o.render), 0) << "the warning says black";
  EXPECT_EQ(max_of(o.trace), 0) << "the warning says black";
  EXPECT_FALSE(warned(o, "render", "no UVs"));
}

TEST(RenderWarnings, ALitSceneWithUvsHasNeitherWarningAndShowsItsTexture) {
  const Outcome o = run(test::temp_dir(), true, true);
  ASSERT_EQ(o.code, 0) << o.output;
  for (const char* node : {"render", "trace"}) {
    EXPECT_FALSE(warned(o, node, kUnlit));
    EXPECT_FALSE(warned(o, node, "no UVs"));
  }
  EXPECT_GT(max_of(o.render), 20);
  EXPECT_GT(max_of(o.trace), 20);
  EXPECT_GT(spread_on_quad(o.render), 20) << "checker squares";
  EXPECT_GT(spread_on_quad(o.trace), 20) << "checker squares";
}

TEST(RenderWarnings, ATextureOnAMeshWithoutUvsIsAWarningAndShowsAsOneColor) {
  const Outcome o = run(test::temp_dir(), false, true);
  ASSERT_EQ(o.code, 0) << o.output;
  EXPECT_TRUE(warned(o, "render", kNoUvs));
  EXPECT_TRUE(warned(o, "trace", kNoUvs));
  EXPECT_FALSE(warned(o, "render", kUnlit));
  EXPECT_GT(max_of(o.render), 20);
  EXPECT_LT(spread_on_quad(o.render), 3) << "no checker squares: the map is not placed";
}

}  // namespace
}  // namespace loom
