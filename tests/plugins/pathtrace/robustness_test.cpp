// Degenerate input never gives NaN or Inf: degenerate and zero-area emissive
// triangles, a black environment, roughness 0 and 1 for every model, grazing
// geometry; and the image does not depend on the thread count.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include "cornell_box_scene.hpp"
#include "sphere_mesh.hpp"
#include "test_scenes.hpp"

namespace {

using namespace loom::pathtrace;
using loom::Material;

loom::Scene stress_scene(double roughness, bool environment) {
  CornellBoxOptions o;
  o.contents = CornellContents::empty;
  loom::Scene scene = cornell_box(o);
  const Material::Model models[] = {Material::Model::diffuse, Material::Model::plastic,
                                    Material::Model::conductor, Material::Model::dielectric};
  for (int i = 0; i < 4; ++i) {
    loom::SceneObject ball;
    ball.mesh = sphere_mesh(Eigen::Vector3d(90 + 125 * i, 80, 280), 60, 12, 24);
    ball.material.model = models[i];
    ball.material.roughness = roughness;
    ball.material.base_color = Eigen::Vector3d(0.9, 0.6, 0.3);
    scene.objects.push_back(ball);
  }
  // Degenerate triangles: collinear, repeated vertices; one is an emitter of zero area.
  auto bad = std::make_shared<loom::Mesh>();
  bad->V.resize(6, 3);
  bad->V << 100, 300, 300, 200, 300, 300, 300, 300, 300, 250, 400, 250, 250, 400, 250, 250, 400, 250;
  bad->F.resize(2, 3);
  bad->F << 0, 1, 2, 3, 4, 5;
  loom::SceneObject degenerate;
  degenerate.mesh = bad;
  degenerate.material.emission = Eigen::Vector3d(5, 5, 5);
  scene.objects.push_back(degenerate);
  if (environment) scene.environment.map = test::constant_map(16, 8, 0.f);  // black map
  return scene;
}

TEST(PathTraceRobustness, NoNaNOrInfWithDegenerateInput) {
  for (double roughness : {0.0, 1.0, 0.3})
    for (bool env : {false, true})
      for (Strategy strategy : {Strategy::mis, Strategy::nee, Strategy::bsdf}) {
        const loom::Scene scene = stress_scene(roughness, env);
        const EmbreeScene traced(scene);
        RenderSettings s;
        s.width = s.height = 24;
        s.spp = 4;
        s.strategy = strategy;
        const RenderResult r = render(scene, *scene.camera, traced, s);
        EXPECT_EQ(r.nonfinite, 0u) << roughness;
        for (const cv::Mat* m : {&r.image, &r.albedo, &r.normal, &r.depth})
          EXPECT_EQ(test::count_nonfinite(*m), 0) << "roughness " << roughness << " env " << env;
        EXPECT_GT(cv::mean(r.image)[0], 0);
      }
}

TEST(PathTraceRobustness, BlackEnvironmentAndNoLightIsBlack) {
  Material m;
  loom::Environment env;
  env.map = test::constant_map(8, 4, 0.f);
  const loom::Scene scene = test::sphere_in_environment(m, env);
  const EmbreeScene traced(scene);
  RenderSettings s;
  s.width = s.height = 8;
  s.spp = 2;
  const RenderResult r = render(scene, *scene.camera, traced, s);
  EXPECT_EQ(cv::countNonZero(r.image.reshape(1)), 0);
  EXPECT_FALSE(r.environment_sampled);
}

TEST(PathTraceRobustness, SameImageWhateverTheThreadCount) {
  CornellBoxOptions o;
  const loom::Scene scene = cornell_box(o);
  const EmbreeScene traced(scene);
  RenderSettings s;
  s.width = s.height = 48;
  s.spp = 3;
  cv::Mat one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = render(scene, *scene.camera, traced, s).image;
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = render(scene, *scene.camera, traced, s).image;
  }
  EXPECT_EQ(cv::norm(one, two, cv::NORM_INF), 0.0);
  // Adaptive passes draw the same samples: pixels that took all of them (all
  // but those of zero variance, at this threshold) match the single pass.
  s.adaptive_threshold = 1e-9;
  s.adaptive_min_spp = 2;
  const RenderResult adaptive = render(scene, *scene.camera, traced, s);
  int full = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      if (adaptive.samples.at<float>(y, x) != float(s.spp)) continue;
      ++full;
      EXPECT_EQ(adaptive.image.at<cv::Vec3f>(y, x), one.at<cv::Vec3f>(y, x));
    }
  EXPECT_GT(full, s.width * s.height / 2);
}

}  // namespace
