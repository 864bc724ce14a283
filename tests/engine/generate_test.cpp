// Generated meshes: topology by Euler's formula, orientation by signed
// volume, sizes by construction.
#include <cmath>
#include <map>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/testing.hpp"

namespace loom {
namespace {

struct Topology {
  int edges = 0, boundary_edges = 0;
};
Topology topology(const Mesh& m) {
  std::map<std::pair<int, int>, int> count;
  for (int f = 0; f < m.faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      int a = m.F(f, k), b = m.F(f, (k + 1) % 3);
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  Topology t;
  for (const auto& [e, c] : count) {
    ++t.edges;
    t.boundary_edges += c == 1;
  }
  return t;
}

// (1/6) Σ v0 · (v1 × v2): the enclosed volume when faces point outward.
double signed_volume(const Mesh& m) {
  double v = 0;
  for (int f = 0; f < m.faces(); ++f)
    v += m.V.row(m.F(f, 0)).dot(m.V.row(m.F(f, 1)).cross(m.V.row(m.F(f, 2)))) / 6;
  return v;
}

Mesh make(const std::string& type, json inputs) {
  testing::Engine e;
  return e.output<Mesh>({{"loom", 1}, {"seed", 3}, {"nodes", {{"m", {{"type", type}, {"inputs", inputs}}}}}}, "m.mesh");
}

TEST(Generate, DiskIsATopologicalDiskFacingUp) {
  Mesh m = make("DiskMesh", {{"rings", 5}, {"segments", 12}});
  Topology t = topology(m);
  EXPECT_EQ(m.vertices() - t.edges + m.faces(), 1);
  EXPECT_EQ(t.boundary_edges, 12);
  for (int f = 0; f < m.faces(); ++f) {
    Eigen::Vector3d n = (m.V.row(m.F(f, 1)) - m.V.row(m.F(f, 0))).cross(m.V.row(m.F(f, 2)) - m.V.row(m.F(f, 0)));
    EXPECT_GT(n.z(), 0);
  }
}

TEST(Generate, SphereIsClosedAndOutward) {
  Mesh m = make("UVSphere", {{"rings", 40}, {"segments", 80}, {"radius", 2}});
  Topology t = topology(m);
  EXPECT_EQ(m.vertices() - t.edges + m.faces(), 2);
  EXPECT_EQ(t.boundary_edges, 0);
  EXPECT_NEAR(signed_volume(m), 4.0 / 3 * M_PI * 8, 0.05 * 4.0 / 3 * M_PI * 8);
}

TEST(Generate, HemisphereHasOneBoundaryOnTheEquatorAndSeededNoise) {
  Mesh m = make("HemisphereMesh", {{"rings", 8}, {"segments", 32}});
  EXPECT_EQ(topology(m).boundary_edges, 32);
  EXPECT_NEAR(m.V.col(2).minCoeff(), 0.0, 1e-12);
  Mesh a = make("HemisphereMesh", {{"noise", 0.1}});
  Mesh b = make("HemisphereMesh", {{"noise", 0.1}});
  EXPECT_EQ(a.V, b.V);  // same graph seed, same node id: same noise
  EXPECT_GT((a.V - make("HemisphereMesh", json::object()).V).norm(), 0.1);
}

TEST(Generate, GridHasUVsOnTheUnitSquare) {
  Mesh m = make("GridMesh", {{"resolution", {4, 3}}, {"size", {2, 1}}});
  EXPECT_EQ(m.vertices(), 20);
  EXPECT_EQ(m.faces(), 24);
  EXPECT_DOUBLE_EQ(m.UV.maxCoeff(), 1.0);
  EXPECT_DOUBLE_EQ(m.V.col(0).maxCoeff(), 1.0);
}

TEST(Generate, CheckerboardHasTwoColorsInCells) {
  testing::Engine e;
  Image img = e.output<Image>(
      {{"loom", 1},
       {"nodes",
        {{"b",
          {{"type", "Checkerboard"},
           {"inputs", {{"size", {40, 20}}, {"cells", 2}, {"color_a", {1, 0, 0}}, {"color_b", "#0000ff"}}}}}}}},
      "b.image");
  EXPECT_EQ(img.encoding, Encoding::srgb);
  EXPECT_EQ(img.pixels.at<cv::Vec3f>(0, 0), cv::Vec3f(1, 0, 0));
  EXPECT_EQ(img.pixels.at<cv::Vec3f>(0, 10), cv::Vec3f(0, 0, 1));
  EXPECT_EQ(img.pixels.at<cv::Vec3f>(10, 10), cv::Vec3f(1, 0, 0));
}

}  // namespace
}  // namespace loom
