// The rasterizer against independent references: analytic Lambert shading
// of a sphere, computed per pixel by intersecting the pixel's ray with the
// exact sphere.
#include <gtest/gtest.h>

#include <cmath>

#include "loom/error.hpp"
#include "rasterizer.hpp"
#include "shading_scenes.hpp"

namespace loom::shading {
namespace {

Rasterizer& rasterizer() {
  static Rasterizer r;
  return r;
}

TEST(Rasterizer, ContextIsCoreProfileLlvmpipe) {
  EXPECT_NE(rasterizer().renderer().find("llvmpipe"), std::string::npos) << rasterizer().renderer();
  EXPECT_GE(rasterizer().max_samples(), 4);
}

// A unit sphere under a directional light: outgoing radiance albedo/pi * E *
// max(n.l, 0) (no specular, no ambient), compared per pixel with the exact
// sphere hit by the pixel-center ray; pixels near the silhouette excluded.
double worst_lambert_error(const SceneObject& unit_sphere, int* compared_out) {
  Scene scene;
  scene.objects.push_back(unit_sphere);
  Light sun;
  sun.kind = Light::Kind::directional;
  sun.direction = Eigen::Vector3d(-1, -0.5, -0.8).normalized();
  sun.intensity = 2.5;
  sun.casts_shadow = false;
  scene.lights.push_back(sun);
  Camera cam;
  cam.eye = {0.3, 0.4, 4};
  cam.target = {0, 0, 0};
  cam.fov_y = 0.7;
  cam.near_plane = 0.1;
  cam.far_plane = 100;
  scene.camera = cam;
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  o.shadows = ShadowFilter::off;
  const RenderImages r = rasterizer().render(scene, o);
  EXPECT_EQ(r.color.cols, 320);

  // Camera frame (independent of the renderer's matrices).
  const Eigen::Vector3d f = (cam.target - cam.eye).normalized();
  const Eigen::Vector3d s = f.cross(cam.up).normalized(), u = s.cross(f);
  const double t = std::tan(cam.fov_y / 2), aspect = 320.0 / 240;
  const Eigen::Vector3d albedo(0.7, 0.5, 0.3), L = -sun.direction;
  double worst = 0;
  int compared = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const double px = (2 * (x + 0.5) / o.width - 1) * t * aspect, py = (1 - 2 * (y + 0.5) / o.height) * t;
      const Eigen::Vector3d d = (f + px * s + py * u).normalized();
      // |e + t d| = 1: t² + 2 (e.d) t + |e|² - 1 = 0.
      const double b = cam.eye.dot(d), c = cam.eye.squaredNorm() - 1, disc = b * b - c;
      const cv::Vec4f p = r.color.at<cv::Vec4f>(y, x);
      // Away from the silhouette: the ray enters well inside the disk.
      if (disc < 0.02) continue;
      const Eigen::Vector3d n = cam.eye + (-b - std::sqrt(disc)) * d;
      const Eigen::Vector3d expected = albedo / M_PI * sun.intensity * std::max(0.0, n.dot(L));
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(p[k] - expected[k]));
      EXPECT_EQ(p[3], 1.0f) << x << " " << y;
      ++compared;
    }
  // Background: no coverage, black (no environment).
  EXPECT_EQ(r.color.at<cv::Vec4f>(0, 0)[3], 0.0f);
  *compared_out = compared;
  return worst;
}

TEST(Rasterizer, SphereMatchesAnalyticLambert) {
  int compared = 0;
  const double worst = worst_lambert_error(scenes::object(scenes::sphere(256, 512), {0.7, 0.5, 0.3}), &compared);
  EXPECT_GT(compared, 20000);
  EXPECT_LE(worst, 1.0 / 255) << "worst per-channel error";
}

// The albedo from the mesh's vertex colours (base colour white): the
// program reads them only for meshes that have them.
TEST(Rasterizer, VertexColoursAreTheAlbedo) {
  Mesh sphere = scenes::sphere(256, 512);
  sphere.C = Eigen::RowVector3d(0.7, 0.5, 0.3).replicate(sphere.V.rows(), 1);
  int compared = 0;
  const double worst = worst_lambert_error(scenes::object(sphere, {1, 1, 1}), &compared);
  EXPECT_GT(compared, 20000);
  EXPECT_LE(worst, 1.0 / 255) << "worst per-channel error";
}

// A point set of one point, radius 1, drawn as a sphere impostor: exact.
TEST(Rasterizer, PointImpostorMatchesAnalyticLambert) {
  SceneObject o;
  auto points = std::make_shared<PointSet>();
  points->P = Eigen::MatrixX3d::Zero(1, 3);
  points->radius = Eigen::VectorXd::Ones(1);
  points->C = Eigen::RowVector3d(0.7, 0.5, 0.3);
  o.points = points;
  o.material.base_color = {1, 1, 1};
  o.material.specular = 0;
  int compared = 0;
  const double worst = worst_lambert_error(o, &compared);
  EXPECT_GT(compared, 20000);
  EXPECT_LE(worst, 1.0 / 255) << "worst per-channel error";
}

// Points keep their own radius and color; points without radius use the option's.
TEST(Rasterizer, PointsAndLinesReachThePicture) {
  Scene scene;
  SceneObject pts;
  auto points = std::make_shared<PointSet>();
  points->P.resize(2, 3);
  points->P << -1, 0, 0, 1, 0, 0;
  points->C.resize(2, 3);
  points->C << 1, 0, 0, 0, 0, 1;
  pts.points = points;
  pts.material.base_color = {1, 1, 1};
  pts.material.specular = 0;
  scene.objects.push_back(pts);
  SceneObject lines;
  auto l = std::make_shared<Polylines>();
  l->P.resize(2, 3);
  l->P << -2, -1, 0, 2, -1, 0;
  l->E.resize(1, 2);
  l->E << 0, 1;
  l->C = Eigen::MatrixX3d::Constant(2, 3, 0.5);
  l->C.col(1).setOnes();
  lines.lines = l;
  scene.objects.push_back(lines);
  Light sun;
  sun.kind = Light::Kind::directional;
  sun.direction = {0, 0, -1};
  scene.lights.push_back(sun);
  Camera cam;
  cam.projection = Camera::Projection::orthographic;
  cam.eye = {0, 0, 5};
  cam.ortho_height = 4;  // 100 px per unit at 400 px high
  scene.camera = cam;
  RenderOptions o;
  o.width = o.height = 400;
  o.point_radius = 0.3;
  o.line_width = 3;
  const RenderImages r = rasterizer().render(scene, o);
  // Point centers at x = 100 and 300, y = 200; radius 30 px.
  const cv::Vec4f red = r.color.at<cv::Vec4f>(200, 100), blue = r.color.at<cv::Vec4f>(200, 300);
  EXPECT_GT(red[0], 0.1f);
  EXPECT_EQ(red[2], 0.0f);
  EXPECT_GT(blue[2], 0.1f);
  EXPECT_EQ(blue[0], 0.0f);
  EXPECT_EQ(r.color.at<cv::Vec4f>(200, 100 + 35)[3], 0.0f);  // outside the radius
  EXPECT_EQ(r.color.at<cv::Vec4f>(200, 100 + 25)[3], 1.0f);  // inside it
  // The line at y = -1 (row 300) is unlit green-ish (0.5, 1, 0.5).
  const cv::Vec4f g = r.color.at<cv::Vec4f>(300, 200);
  EXPECT_NEAR(g[1], 1.0f, 1e-3);
  EXPECT_NEAR(g[0], 0.5f, 1e-3);
}

TEST(Rasterizer, InvalidSceneAndOptionsFailClearly) {
  Scene scene;
  SceneObject o;
  scene.objects.push_back(o);  // no geometry
  EXPECT_THROW(rasterizer().render(scene, {}), Error);
  scene.objects.clear();
  RenderOptions bad;
  bad.width = 0;
  EXPECT_THROW(rasterizer().render(scene, bad), Error);
  RenderOptions huge;
  huge.width = huge.height = 16384;
  huge.samples = 4;
  EXPECT_THROW(rasterizer().render(scene, huge), Error);
  // An empty scene renders the background.
  RenderOptions tiny;
  tiny.width = tiny.height = 8;
  const RenderImages r = rasterizer().render(scene, tiny);
  EXPECT_EQ(cv::countNonZero(r.color.reshape(1)), 0);
}

}  // namespace
}  // namespace loom::shading
