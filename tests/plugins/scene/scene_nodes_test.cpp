// The scene assembly nodes through the engine: transforms against hand-built
// matrices, merging rules, and refusals of bad input.
#include <chrono>
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "loom/scene.hpp"
#include "loom/testing.hpp"
#include "test_files.hpp"

namespace {

using loom::json;

json object_graph(const json& object_inputs) {
  json object = {{"type", "Object"}, {"inputs", object_inputs}};
  if (!object["inputs"].contains("mesh") && !object["inputs"].contains("points"))
    object["inputs"]["mesh"] = {{"from", "sphere.mesh"}};
  return {{"loom", 1},
          {"nodes",
           {{"sphere", {{"type", "UVSphere"}, {"inputs", {{"rings", 4}, {"segments", 8}}}}},
            {"object", object}}}};
}

TEST(SceneNodes, ObjectTransformScalesThenRotatesThenTranslates) {
  loom::testing::Engine engine;
  const auto doc = object_graph(
      {{"translate", {1, 2, 3}}, {"rotate_degrees", {0, 90, 0}}, {"scale", {2, 1, 1}}});
  const auto& scene = engine.output<loom::Scene>(doc, "object.scene");
  ASSERT_EQ(scene.objects.size(), 1u);
  const Eigen::Matrix4d& T = scene.objects[0].transform;
  // x = (1,0,0) scaled to (2,0,0), turned 90 degrees about +y to (0,0,-2), then moved.
  const Eigen::Vector4d p = T * Eigen::Vector4d(1, 0, 0, 1);
  EXPECT_NEAR((p.head<3>() - Eigen::Vector3d(1, 2, 1)).norm(), 0, 1e-12);
  // Bounds of the placed unit sphere: x in [0, 2] (radius 1 along z -> x after the turn),
  // z in [3 - 2, 3 + 2] (scaled radius 2 along x -> z).
  const Eigen::AlignedBox3d box = loom::bounds(scene);
  EXPECT_NEAR(box.min().z(), 1, 1e-9);
  EXPECT_NEAR(box.max().z(), 5, 1e-9);
  EXPECT_NO_THROW(loom::require_valid(scene, "scene"));
}

TEST(SceneNodes, ObjectNeedsExactlyOneGeometryAndAValidScale) {
  loom::testing::Engine engine;
  auto doc = object_graph({{"scale", {1, 0, 1}}});
  auto g = engine.load(doc);
  auto r = engine.run(g, {"object"});
  EXPECT_EQ(r.status("object"), loom::NodeStatus::failed);
  EXPECT_NE(r.error("object").find("scale"), std::string::npos);

  doc = object_graph({});
  doc["nodes"]["object"]["inputs"].erase("mesh");
  doc["nodes"]["object"]["inputs"]["name"] = "nothing";
  r = engine.run(doc, {"object"});
  EXPECT_EQ(r.status("object"), loom::NodeStatus::failed);
  EXPECT_NE(r.error("object").find("exactly one"), std::string::npos);
}

TEST(SceneNodes, MergeConcatenatesAndTheLastCameraWins) {
  loom::testing::Engine engine;
  json doc = object_graph({});
  auto& n = doc["nodes"];
  n["light"] = {{"type", "Light"},
                {"inputs", {{"kind", "spot"}, {"direction", {0, -2, 0}}, {"spot_inner_degrees", 10}}}};
  n["cam1"] = {{"type", "Camera"}, {"inputs", {{"eye", {0, 0, 9}}}}};
  n["cam2"] = {{"type", "Camera"}, {"inputs", {{"eye", {0, 4, 0}}, {"up", {0, 0, -1}}, {"fov_degrees", 90}}}};
  n["env"] = {{"type", "Environment"}, {"inputs", {{"color", {0.5, 0.5, 0.5}}, {"intensity", 2}}}};
  n["merge"] = {{"type", "MergeScenes"},
                {"inputs",
                 {{"a", {{"from", "object.scene"}}},
                  {"b", {{"from", "cam1.scene"}}},
                  {"c", {{"from", "light.scene"}}},
                  {"d", {{"from", "object.scene"}}},
                  {"e", {{"from", "env.scene"}}},
                  {"f", {{"from", "cam2.scene"}}}}}};
  auto g = engine.load(doc);
  auto r = engine.run(g, {"merge"});
  ASSERT_EQ(r.status("merge"), loom::NodeStatus::ran) << r.error("merge");
  const auto& scene = r.output<loom::Scene>("merge");
  EXPECT_EQ(scene.objects.size(), 2u);
  ASSERT_EQ(scene.lights.size(), 1u);
  EXPECT_EQ(scene.lights[0].kind, loom::Light::Kind::spot);
  EXPECT_NEAR((scene.lights[0].direction - Eigen::Vector3d(0, -1, 0)).norm(), 0, 1e-15);
  EXPECT_NEAR(scene.lights[0].spot_inner, 10 * M_PI / 180, 1e-15);
  ASSERT_TRUE(scene.camera);
  EXPECT_EQ(scene.camera->eye, Eigen::Vector3d(0, 4, 0));
  EXPECT_NEAR(scene.camera->fov_y, M_PI / 2, 1e-15);
  EXPECT_EQ(scene.environment.color, Eigen::Vector3d(0.5, 0.5, 0.5));
  EXPECT_EQ(scene.environment.intensity, 2);
  ASSERT_EQ(r.warnings("merge").size(), 1u);
  EXPECT_NE(r.warnings("merge")[0].find("camera"), std::string::npos);
}

TEST(SceneNodes, CameraAndLightRefuseDegenerateDirections) {
  loom::testing::Engine engine;
  json doc = {{"loom", 1},
              {"nodes",
               {{"cam", {{"type", "Camera"}, {"inputs", {{"eye", {0, 5, 0}}, {"up", {0, 1, 0}}}}}},
                {"same", {{"type", "Camera"}, {"inputs", {{"eye", {0, 0, 0}}}}}},
                {"light", {{"type", "Light"}, {"inputs", {{"kind", "directional"}, {"direction", {0, 0, 0}}}}}},
                {"spot",
                 {{"type", "Light"},
                  {"inputs", {{"kind", "spot"}, {"spot_inner_degrees", 40}, {"spot_outer_degrees", 30}}}}}}}};
  auto r = engine.run(doc, {"cam", "same", "light", "spot"});
  for (const char* id : {"cam", "same", "light", "spot"})
    EXPECT_EQ(r.result().nodes.at(id).status, loom::NodeStatus::failed) << id;
  EXPECT_NE(r.error("cam").find("up"), std::string::npos);
  EXPECT_NE(r.error("light").find("direction"), std::string::npos);
}

TEST(SceneNodes, MaterialDecodesSRGBColorMapsAndKeepsNormalMapsAsStored) {
  loom::testing::Engine engine;
  json doc = {{"loom", 1},
              {"nodes",
               {{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {8, 8}}, {"cells", 2}}}}},
                {"material",
                 {{"type", "Material"},
                  {"inputs",
                   {{"model", "conductor"},
                    {"base_color", {0.9, 0.6, 0.2}},
                    {"base_color_map", {{"from", "board.image"}}},
                    {"normal_map", {{"from", "board.image"}}},
                    {"emission", {1, 2, 3}},
                    {"emission_strength", 2}}}}}}}};
  const auto& board = engine.output<loom::Image>(doc, "board.image");
  const auto& m = engine.output<loom::Material>(doc, "material.material");
  EXPECT_EQ(m.model, loom::Material::Model::conductor);
  EXPECT_EQ(m.emission, Eigen::Vector3d(2, 4, 6));
  ASSERT_TRUE(m.base_color_map && m.normal_map);
  EXPECT_EQ(m.base_color_map->encoding, loom::Encoding::linear);
  // The normal map is the very image linked (no copy, no conversion).
  EXPECT_EQ(m.normal_map->pixels.data, board.pixels.data);
  if (board.encoding == loom::Encoding::srgb) {
    const float v = board.pixels.at<cv::Vec3f>(0, 0)[0];
    EXPECT_NEAR(m.base_color_map->pixels.at<cv::Vec3f>(0, 0)[0], loom::srgb_to_linear(v), 1e-6);
  }
}


// A square of two triangles in glTF, as positions (float32) and uint16
// indices in one data URI.
std::string square_gltf(int vertices, const std::string& base64, int position_bytes) {
  const json doc = {
      {"asset", {{"version", "2.0"}}},
      {"buffers", {{{"uri", "data:application/octet-stream;base64," + base64}, {"byteLength", position_bytes + 12}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteLength", position_bytes}},
                       {{"buffer", 0}, {"byteOffset", position_bytes}, {"byteLength", 12}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", vertices}, {"type", "VEC3"},
                      {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
                     {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"scenes", {{{"nodes", {0}}}}}};
  return doc.dump();
}

const loom::Mesh& loaded_mesh(loom::testing::Engine& engine, const std::filesystem::path& file) {
  const json doc = {{"loom", 1}, {"nodes", {{"load", {{"type", "LoadScene"}, {"inputs", {{"path", file.string()}}}}}}}};
  const auto& scene = engine.output<loom::Scene>(doc, "load.scene");
  EXPECT_EQ(scene.objects.size(), 1u);
  return *scene.objects.at(0).mesh;
}

// Issue 26 item 7: LoadScene converts meshes as LoadMesh does (one
// conversion, loom/formats/assimp_import.hpp): a mesh keeps its own vertices.
// A square cut along its diagonal (the two sides' vertices at the same
// positions, as a mesh prepared for parameterization has) stays cut; the
// same square with a shared edge keeps its 4 vertices. JoinIdenticalVertices,
// which LoadScene used, welded the cut to 4.
TEST(SceneNodes, LoadSceneKeepsACutSeamAndTheFilesOwnVertices) {
  const auto dir = loom::test::temp_dir();
  {
    std::ofstream(dir / "cut.gltf") << square_gltf(
        6, "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAACAPwAAAAAAAAAAAACAPwAAgD8AAAAAAAAAAAAAgD8AAAAAAAABAAIAAwAEAAUA", 72);
    std::ofstream(dir / "shared.gltf") << square_gltf(
        4, "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAACAPwAAgD8AAAAAAAABAAIAAQADAAIA", 48);
    std::ofstream(dir / "cut.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 4 5 6\n";
  }
  loom::testing::Engine engine;
  for (const char* cut : {"cut.gltf", "cut.obj"}) {
    const loom::Mesh& m = loaded_mesh(engine, dir / cut);
    ASSERT_EQ(m.faces(), 2) << cut;
    EXPECT_EQ(m.vertices(), 6) << cut;
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l) EXPECT_NE(m.F(0, k), m.F(1, l)) << cut << ": the seam was welded";
  }
  const loom::Mesh& shared = loaded_mesh(engine, dir / "shared.gltf");
  EXPECT_EQ(shared.vertices(), 4);
  EXPECT_EQ(shared.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(shared.F.row(1), Eigen::RowVector3i(1, 3, 2));
}

// Issue 30 item 3 for LoadScene: the .mtl and the textures it reads are part of
// its result's identity (declared with Context::depends_on_file), so a changed
// material colour or texture is read again, not served from the cache.
TEST(SceneNodes, LoadSceneRereadsAChangedMtlOrTexture) {
  namespace fs = std::filesystem;
  const auto dir = loom::test::temp_dir();
  auto write = [&](const char* name, const std::string& text) {
    std::ofstream(dir / name) << text;
    static int tick = 0;  // a later modification time each write, whatever the clock's resolution
    fs::last_write_time(dir / name, fs::file_time_type::clock::now() + std::chrono::seconds(++tick));
  };
  write("s.obj", "mtllib s.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 3 0 0\nv 2 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                 "o a\nusemtl plain\nf 1/1 2/2 3/3\no b\nusemtl textured\nf 4/1 5/2 6/3\n");
  write("s.mtl", "newmtl plain\nKd 0.8 0.1 0.1\nnewmtl textured\nKd 1 1 1\nmap_Kd t.ppm\n");
  write("t.ppm", "P3\n1 1\n255\n255 255 255\n");
  loom::testing::Engine engine;
  const loom::Graph g = engine.load(
      {{"loom", 1}, {"nodes", {{"load", {{"type", "LoadScene"}, {"inputs", {{"path", "s.obj"}}}}}}}}, dir / "g.json");
  auto colours = [&] {  // the plain material's red, the texture's red
    loom::testing::Run r = engine.run(g, {"load.scene"});
    const auto& scene = r.output<loom::Scene>("load.scene");
    double plain = -1, texel = -1;
    for (const auto& o : scene.objects)
      if (o.material.base_color_map)
        texel = o.material.base_color_map->pixels.at<cv::Vec3f>(0, 0)[0];
      else
        plain = o.material.base_color.x();
    return std::pair<double, double>(plain, texel);
  };
  EXPECT_NEAR(colours().first, 0.8, 1e-6);
  EXPECT_EQ(engine.run(g, {"load.scene"}).status("load"), loom::NodeStatus::cached);
  write("s.mtl", "newmtl plain\nKd 0.2 0.1 0.1\nnewmtl textured\nKd 1 1 1\nmap_Kd t.ppm\n");
  EXPECT_NEAR(colours().first, 0.2, 1e-6);
  EXPECT_NEAR(colours().second, 1.0, 1e-6);
  write("t.ppm", "P3\n1 1\n255\n0 0 0\n");
  EXPECT_NEAR(colours().second, 0.0, 1e-6);
}

}  // namespace
