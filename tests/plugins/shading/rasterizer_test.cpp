// The rasterizer against independent references: analytic Lambert shading
// of a sphere, computed per pixel by intersecting the pixel's ray with the
// exact sphere.
#include <gtest/gtest.h>

#include <cmath>

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
TEST(Rasterizer, SphereMatchesAnalyticLambert) {
  Scene scene;
  scene.objects.push_back(scenes::object(scenes::sphere(256, 512), {0.7, 0.5, 0.3}));
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
  ASSERT_EQ(r.color.cols, 320);

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
      ASSERT_EQ(p[3], 1.0f) << x << " " << y;
      ++compared;
    }
  EXPECT_GT(compared, 20000);
  EXPECT_LE(worst, 1.0 / 255) << "worst per-channel error";
  // Background: no coverage, black (no environment).
  EXPECT_EQ(r.color.at<cv::Vec4f>(0, 0)[3], 0.0f);
}

}  // namespace
}  // namespace loom::shading
