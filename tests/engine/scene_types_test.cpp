// The shared render and simulation types: Scene, PointSet, Polylines, and the
// lat-long map convention both renderers use.
#include <cmath>

#include <gtest/gtest.h>

#include "loom/scene.hpp"
#include "loom/serialize.hpp"

namespace loom {
namespace {

TEST(SceneTypes, LatLongRoundTripsEveryDirection) {
  for (double theta = 0.05; theta < 3.1; theta += 0.1)
    for (double phi = -3.1; phi < 3.1; phi += 0.1)
      for (double rotation : {0.0, 1.3}) {
        const Eigen::Vector3d d(std::sin(theta) * std::cos(phi), std::cos(theta),
                                std::sin(theta) * std::sin(phi));
        const Eigen::Vector2d uv = latlong_uv(d, rotation);
        ASSERT_GE(uv.x(), 0);
        ASSERT_LT(uv.x(), 1);
        EXPECT_NEAR((latlong_direction(uv, rotation) - d).norm(), 0, 1e-12);
      }
  // The documented anchors: top row is +y, the middle column looks down -z.
  EXPECT_NEAR(latlong_uv({0, 1, 0}).y(), 0, 1e-12);
  EXPECT_NEAR((latlong_direction({0.5, 0.5}) - Eigen::Vector3d(0, 0, -1)).norm(), 0, 1e-12);
}

TEST(SceneTypes, BoundsCoverTransformedGeometryAndPointRadii) {
  Scene scene;
  auto mesh = std::make_shared<Mesh>();
  mesh->V = (Eigen::MatrixX3d(3, 3) << 0, 0, 0, 1, 0, 0, 0, 1, 0).finished();
  mesh->F = (Eigen::MatrixX3i(1, 3) << 0, 1, 2).finished();
  SceneObject tri;
  tri.mesh = mesh;
  tri.transform(0, 3) = 10;  // moved along +x
  scene.objects.push_back(tri);
  auto points = std::make_shared<PointSet>();
  points->P = Eigen::RowVector3d(0, 0, -5);
  points->radius = Eigen::VectorXd::Constant(1, 0.5);
  SceneObject cloud;
  cloud.points = points;
  scene.objects.push_back(cloud);
  const Eigen::AlignedBox3d box = bounds(scene);
  EXPECT_DOUBLE_EQ(box.min().x(), -0.5);
  EXPECT_DOUBLE_EQ(box.max().x(), 11);
  EXPECT_DOUBLE_EQ(box.min().z(), -5.5);
  EXPECT_DOUBLE_EQ(box.max().y(), 1);

  const Camera camera = framing_camera(scene, 16.0 / 9);
  // Every corner of the box is inside the camera's vertical field of view.
  const Eigen::Vector3d forward = (camera.target - camera.eye).normalized();
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d to = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)) - camera.eye;
    EXPECT_LT(std::acos(to.normalized().dot(forward)), camera.fov_y / 2);
  }
  EXPECT_NO_THROW(require_valid(scene, "scene"));
}

TEST(SceneTypes, InvalidScenesNameWhatIsWrong) {
  Scene scene;
  scene.objects.emplace_back();
  scene.objects.back().name = "empty";
  try {
    require_valid(scene, "scene");
    FAIL() << "an object without geometry was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("object 0 (empty)"), std::string::npos) << e.what();
  }
  scene.objects.back().points = std::make_shared<PointSet>();
  scene.objects.back().material.roughness = 2;
  EXPECT_THROW(require_valid(scene, "scene"), Error);
  scene.objects.back().material.roughness = 0.5;
  scene.lights.emplace_back();
  scene.lights.back().intensity = std::nan("");
  EXPECT_THROW(require_valid(scene, "scene"), Error);
}

TEST(SceneTypes, PointSetAndPolylinesValidation) {
  PointSet p;
  p.P = Eigen::MatrixX3d::Zero(2, 3);
  p.radius = Eigen::VectorXd::Constant(3, 1.0);
  EXPECT_THROW(require_valid(p, "points"), Error);
  p.radius = Eigen::VectorXd::Constant(2, 1.0);
  EXPECT_NO_THROW(require_valid(p, "points"));
  Polylines l;
  l.P = Eigen::MatrixX3d::Zero(2, 3);
  l.E = (Eigen::MatrixX2i(1, 2) << 0, 2).finished();
  EXPECT_THROW(require_valid(l, "lines"), Error);
}

TEST(Serialize, ReaderNeverReadsPastTheEnd) {
  ByteWriter w;
  w.matrix(Eigen::MatrixX3d::Ones(4, 3).eval());
  w.str("hello");
  w.vector(std::vector<int>{1, 2, 3});
  const auto& b = w.buffer();
  ByteReader r(b.data(), b.size());
  EXPECT_EQ(r.matrix<Eigen::MatrixX3d>(), Eigen::MatrixX3d::Ones(4, 3));
  EXPECT_EQ(r.str(), "hello");
  EXPECT_EQ(r.vector<int>(), (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(r.at_end());
  // Every truncation is refused, never read out of bounds.
  for (std::size_t n = 0; n < b.size(); ++n) {
    ByteReader t(b.data(), n);
    EXPECT_THROW(
        {
          t.matrix<Eigen::MatrixX3d>();
          t.str();
          t.vector<int>();
        },
        Error)
        << n;
  }
}

}  // namespace
}  // namespace loom
