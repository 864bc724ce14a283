// LoadScene (plugin scene) through the engine: an OBJ + MTL with a texture
// written here, read back as objects, materials and maps.
#include <gtest/gtest.h>

#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "loom/scene.hpp"
#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

TEST(LoadScene, ObjWithMtlAndTextures) {
  const auto dir = test::temp_dir();
  // A 2x1 texture: left pixel sRGB 188 (linear ~0.5), right pixel black.
  cv::Mat tex(1, 2, CV_8UC3, cv::Scalar(0, 0, 0));
  tex.at<cv::Vec3b>(0, 0) = cv::Vec3b(188, 188, 188);
  ASSERT_TRUE(cv::imwrite((dir / "wood.png").string(), tex));
  std::ofstream(dir / "two.mtl") << "newmtl red\nKd 0.8 0.1 0.1\nKe 0 0 0\nNs 100\n"
                                 << "newmtl textured\nKd 1 1 1\nmap_Kd wood.png\n";
  std::ofstream(dir / "two.obj") << "mtllib two.mtl\n"
                                 << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 3 0 0\nv 2 1 0\n"
                                 << "vt 0 0\nvt 1 0\nvt 0 1\n"
                                 << "o a\nusemtl red\nf 1/1 2/2 3/3\n"
                                 << "o b\nusemtl textured\nf 4/1 5/2 6/3\n";
  testing::Engine engine;
  const json g = {{"loom", 1},
                  {"nodes", {{"load", {{"type", "LoadScene"}, {"inputs", {{"path", (dir / "two.obj").string()}}}}}}}};
  const Scene& scene = engine.output<Scene>(g, "load.scene");
  ASSERT_EQ(scene.objects.size(), 2u);
  bool saw_red = false, saw_textured = false;
  for (const SceneObject& o : scene.objects) {
    ASSERT_TRUE(o.mesh);
    EXPECT_EQ(o.mesh->faces(), 1);
    EXPECT_TRUE(o.mesh->has_uv());
    if (o.material.base_color_map) {
      saw_textured = true;
      const Image& t = *o.material.base_color_map;
      EXPECT_EQ(t.encoding, Encoding::linear);
      EXPECT_NEAR(t.pixels.at<cv::Vec3f>(0, 0)[0], srgb_to_linear(188 / 255.0f), 1e-4);
    } else {
      saw_red = true;
      EXPECT_NEAR(o.material.base_color.x(), 0.8, 1e-6);
      EXPECT_NEAR(o.material.base_color.y(), 0.1, 1e-6);
      EXPECT_LT(o.material.roughness, 0.5);  // Ns 100 is fairly glossy
    }
  }
  EXPECT_TRUE(saw_red);
  EXPECT_TRUE(saw_textured);
}

// A hand-written glTF 2.0: one triangle under a translated node, a metallic
// PBR material; the buffer is embedded as base64.
TEST(LoadScene, GltfNodeTransformAndPbrMaterial) {
  const auto dir = test::temp_dir();
  std::ofstream(dir / "tri.gltf") << R"({
  "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0, "translation": [1, 2, 3]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
  "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.2, 1], "metallicFactor": 1.0,
                                          "roughnessFactor": 0.3}}],
  "buffers": [{"byteLength": 42,
               "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIA"}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]
})";
  testing::Engine engine;
  const json g = {{"loom", 1},
                  {"nodes", {{"load", {{"type", "LoadScene"}, {"inputs", {{"path", (dir / "tri.gltf").string()}}}}}}}};
  const Scene& scene = engine.output<Scene>(g, "load.scene");
  ASSERT_EQ(scene.objects.size(), 1u);
  const SceneObject& o = scene.objects[0];
  EXPECT_EQ(o.mesh->faces(), 1);
  EXPECT_NEAR(o.transform(0, 3), 1, 1e-12);
  EXPECT_NEAR(o.transform(1, 3), 2, 1e-12);
  EXPECT_NEAR(o.transform(2, 3), 3, 1e-12);
  EXPECT_EQ(o.material.model, Material::Model::conductor);
  EXPECT_NEAR(o.material.base_color.x(), 0.9, 1e-6);
  EXPECT_NEAR(o.material.base_color.z(), 0.2, 1e-6);
  EXPECT_NEAR(o.material.roughness, 0.3, 1e-6);
}

TEST(LoadScene, MissingFileFailsClearly) {
  testing::Engine engine;
  const json g = {{"loom", 1},
                  {"nodes", {{"load", {{"type", "LoadScene"}, {"inputs", {{"path", "/nonexistent/x.gltf"}}}}}}}};
  testing::Run r = engine.run(g, {"load.scene"});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error("load").find("x.gltf"), std::string::npos) << r.error("load");
}

}  // namespace
}  // namespace loom
