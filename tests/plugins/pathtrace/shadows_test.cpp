// Light.casts_shadow: next-event estimation from a light with casts_shadow
// off traces no shadow ray, so an occluder between it and the floor changes
// nothing; with it on, the occluded floor is black (direct light only).
#include <cmath>

#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace {

using namespace loom::pathtrace;

constexpr double kPiD = 3.14159265358979323846;

std::shared_ptr<loom::Mesh> square(double half, double y) {
  auto m = std::make_shared<loom::Mesh>();
  m->V.resize(4, 3);
  m->V << -half, y, -half, half, y, -half, half, y, half, -half, y, half;
  m->F.resize(2, 3);
  m->F << 0, 2, 1, 0, 3, 2;  // facing +y
  return m;
}

// A floor, optionally a small square 1 above its centre, a point light 3
// above it; the camera looks at the floor's centre from the side, under the
// occluder.
loom::Scene floor_scene(bool occluder, bool light_casts_shadow) {
  loom::Scene scene;
  loom::SceneObject floor;
  floor.mesh = square(2, 0);
  floor.material.base_color = Eigen::Vector3d(0.6, 0.6, 0.6);
  scene.objects.push_back(floor);
  if (occluder) {
    loom::SceneObject o;
    o.mesh = square(0.5, 1);
    scene.objects.push_back(o);
  }
  loom::Light light;
  light.kind = loom::Light::Kind::point;
  light.position = Eigen::Vector3d(0, 3, 0);
  light.intensity = 9;
  light.casts_shadow = light_casts_shadow;
  scene.lights.push_back(light);
  loom::Camera camera;
  camera.eye = Eigen::Vector3d(3, 0.5, 0);
  camera.target = Eigen::Vector3d::Zero();
  camera.fov_y = 0.02;
  scene.camera = camera;
  return scene;
}

cv::Mat direct(const loom::Scene& scene, std::uint64_t* rays = nullptr) {
  RenderSettings s;
  s.width = s.height = 5;
  s.spp = 4;
  s.max_depth = 1;
  const EmbreeScene traced(scene);
  const RenderResult r = render(scene, *scene.camera, traced, s);
  if (rays) *rays = r.rays;
  return r.image;
}

TEST(CastsShadow, LightWithoutShadowsIgnoresTheOccluder) {
  std::uint64_t rays_open = 0, rays_unshadowed = 0;
  const cv::Mat open = direct(floor_scene(false, true), &rays_open);
  const cv::Mat shadowed = direct(floor_scene(true, true));
  const cv::Mat unshadowed = direct(floor_scene(true, false), &rays_unshadowed);
  // Irradiance I / d² = 9 / 9 at normal incidence: L = ρ / π near the centre.
  const cv::Vec3f centre = open.at<cv::Vec3f>(2, 2);
  EXPECT_NEAR(centre[0], 0.6 / kPiD, 0.01 * 0.6 / kPiD);
  EXPECT_EQ(cv::norm(open, unshadowed, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(shadowed, cv::NORM_INF), 0);
  // No shadow rays at all: one camera ray per path.
  EXPECT_EQ(rays_unshadowed, 5u * 5 * 4);
  EXPECT_EQ(rays_open, 2u * 5 * 5 * 4);
}

}  // namespace
