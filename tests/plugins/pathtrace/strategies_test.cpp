// The three estimators (BSDF sampling only, light sampling only, MIS) and the
// two environment samplers compute the same integral: their image means agree
// within noise. BSDF-only sampling never touches the light sampler's
// densities, so this checks light selection, area and environment pdfs and
// the MIS weights against an estimator that shares none of them.
#include <gtest/gtest.h>

#include "cornell_box_scene.hpp"
#include "sphere_mesh.hpp"
#include "test_scenes.hpp"

namespace {

using namespace loom::pathtrace;

using test::MeanAndError;

MeanAndError image_mean(const loom::Scene& scene, const RenderSettings& s, int K) {
  return test::image_mean(scene, s, K, 500);
}

void expect_agree(const MeanAndError& a, const MeanAndError& b, const char* what) {
  EXPECT_LT(std::abs(a.mean - b.mean), 3 * std::hypot(a.se, b.se) + 1e-6)
      << what << ": " << a.mean << " ± " << a.se << " vs " << b.mean << " ± " << b.se;
}

TEST(Strategies, AgreeOnTheCornellBox) {
  CornellBoxOptions o;
  const loom::Scene scene = cornell_box(o);
  RenderSettings s;
  s.width = s.height = 16;
  s.spp = 64;
  s.max_depth = 4;
  s.strategy = Strategy::mis;
  const auto mis = image_mean(scene, s, 40);
  s.strategy = Strategy::nee;
  const auto nee = image_mean(scene, s, 12);
  s.strategy = Strategy::bsdf;
  const auto bsdf = image_mean(scene, s, 40);
  expect_agree(mis, nee, "mis/nee");
  expect_agree(mis, bsdf, "mis/bsdf");
  EXPECT_LT(mis.se, bsdf.se);
}

TEST(Strategies, AgreeUnderAnEnvironmentMapWithABrightPixel) {
  loom::Scene scene;
  loom::SceneObject ball;
  ball.mesh = sphere_mesh(Eigen::Vector3d::Zero(), 1, 24, 48);
  ball.material.model = loom::Material::Model::plastic;
  ball.material.roughness = 0.4;
  scene.objects.push_back(ball);
  cv::Mat map(16, 32, CV_32FC3, cv::Scalar::all(0.2));
  map.at<cv::Vec3f>(4, 20) = cv::Vec3f(300, 250, 200);
  scene.environment.map = std::make_shared<loom::Image>(map, loom::Encoding::linear);
  loom::Camera camera;
  camera.eye = Eigen::Vector3d(0, 0, 3);
  camera.target = Eigen::Vector3d::Zero();
  camera.fov_y = 0.9;
  scene.camera = camera;
  RenderSettings s;
  s.width = s.height = 16;
  s.spp = 32;
  s.max_depth = 3;
  const auto importance = image_mean(scene, s, 12);
  s.environment_sampling = EnvironmentLight::Sampling::uniform;
  // Uniform sampling of a 300× brighter pixel is heavy-tailed: the mean of a
  // few renders is mostly low, so it takes more of them.
  const auto uniform = image_mean(scene, s, 60);
  s.environment_sampling = EnvironmentLight::Sampling::importance;
  s.strategy = Strategy::bsdf;
  const auto bsdf = image_mean(scene, s, 40);
  s.strategy = Strategy::nee;
  const auto nee = image_mean(scene, s, 12);
  expect_agree(importance, uniform, "importance/uniform");
  expect_agree(importance, bsdf, "importance/bsdf");
  expect_agree(importance, nee, "importance/nee");
  EXPECT_LT(importance.se, uniform.se);
}

}  // namespace
