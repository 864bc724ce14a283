// The nodes through the engine: generated meshes, and the course meshes when present.
#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

json graph_with(const json& source, const std::string& weights, const std::string& boundary) {
  return {{"loom", 1},
          {"nodes",
           {{"src", source},
            {"flat", {{"type", "Parameterize"},
                      {"inputs", {{"mesh", {{"from", "src.mesh"}}}, {"weights", weights}, {"boundary", boundary}}}}},
            {"layout", {{"type", "UVLayout"}, {"inputs", {{"mesh", {{"from", "flat.mesh"}}}, {"size", 128}}}}}}}};
}

TEST(ParameterizeNodes, HemisphereEveryWeightAndBoundary) {
  testing::Engine engine;
  const json dome = {{"type", "HemisphereMesh"}, {"inputs", {{"rings", 10}, {"segments", 40}, {"noise", 0.02}}}};
  for (const char* w : {"uniform", "cotangent", "cotangent_clamped", "intrinsic_delaunay", "mean_value", "shape_preserving"})
    for (const char* b : {"circle", "square"}) {
      const json g = graph_with(dome, w, b);
      const json report = engine.output<json>(g, "flat.report");
      EXPECT_EQ(report.at("flipped"), 0) << w << " " << b;
      const Mesh& mesh = engine.output<Mesh>(g, "flat.mesh");
      ASSERT_TRUE(mesh.has_uv());
      EXPECT_GE(mesh.UV.minCoeff(), -1e-12);
      EXPECT_LE(mesh.UV.maxCoeff(), 1 + 1e-12);
      const Mesh& flat = engine.output<Mesh>(g, "flat.flattened");
      EXPECT_EQ(flat.V.col(2).cwiseAbs().maxCoeff(), 0.0);
    }
  const json g = graph_with(dome, "mean_value", "circle");
  EXPECT_EQ(engine.output<Image>(g, "layout.image").width(), 128);
}

TEST(ParameterizeNodes, MinimalSurfaceOfABumpyDiskIsFlat) {
  testing::Engine engine;
  const json g = {{"loom", 1},
                  {"nodes",
                   {{"disk", {{"type", "DiskMesh"}, {"inputs", {{"rings", 12}, {"segments", 48}, {"bump_height", 0.3}}}}},
                    {"min", {{"type", "MinimalSurface"}, {"inputs", {{"mesh", {{"from", "disk.mesh"}}}, {"iterations", 2}}}}}}}};
  const Mesh& m = engine.output<Mesh>(g, "min.mesh");
  EXPECT_LT(m.V.col(2).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(ParameterizeNodes, ClosedMeshFailsWithAClearMessage) {
  testing::Engine engine;
  const json g = graph_with({{"type", "UVSphere"}, {"inputs", json::object()}}, "uniform", "circle");
  testing::Run r = engine.run(g, {"flat.mesh"});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error("flat").find("closed"), std::string::npos) << r.error("flat");
}

TEST(ParameterizeNodes, CourseMeshesDoNotFold) {
  testing::Engine engine;
  for (const char* name : {"CatHead", "NefertitiFace", "Isis", "Balls", "BunnyHead", "Beetle"}) {
    LOOM_REQUIRE_DATA(path, std::string("meshes/") + name + ".obj");
    const json load = {{"type", "LoadMesh"}, {"inputs", {{"path", path.string()}}}};
    for (const char* w : {"uniform", "mean_value"}) {
      const json report = engine.output<json>(graph_with(load, w, "circle"), "flat.report");
      EXPECT_EQ(report.at("flipped"), 0) << name << " " << w;
    }
  }
}

TEST(ParameterizeNodes, SphereObjIsRefused) {
  LOOM_REQUIRE_DATA(path, "meshes/sphere.obj");
  testing::Engine engine;
  const json load = {{"type", "LoadMesh"}, {"inputs", {{"path", path.string()}}}};
  testing::Run r = engine.run(graph_with(load, "uniform", "circle"), {"flat.mesh"});
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error("flat").find("closed"), std::string::npos) << r.error("flat");
}

}  // namespace
}  // namespace loom
