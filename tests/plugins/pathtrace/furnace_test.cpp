// White furnace: a sphere of albedo 1 inside a uniform environment of radiance
// 1 reflects exactly 1 everywhere, whatever the number of bounces. Every pixel
// of an energy-conserving material must render to 1 within noise
// (estimated from independent renders), with and without Russian roulette,
// with the environment as a color (BSDF sampling) and as a constant map (light
// sampling + MIS). Standard errors come from 64 independent renders. The
// material and light are white, so the 8×8 pixels give 64 distinct values
// (three equal channels); a fair estimator puts 0.27 % of them (0.17 pixels
// expected) beyond 3 SE, so a case fails when more than 2 pixels are (Poisson
// tail 0.1 %) or any is beyond 4.5 SE; a bias of 3 SE everywhere puts half
// of them outside. (No pixel beyond 3 SE, the old rule, fails a fair case
// 16 % of the time.) Pixels whose estimator has zero variance must equal 1.
#include <gtest/gtest.h>

#include "test_scenes.hpp"

namespace {

using namespace loom::pathtrace;
using loom::Material;

struct FurnaceCase {
  const char* name;
  Material::Model model;
  bool roulette;
  bool map;
};

class Furnace : public ::testing::TestWithParam<FurnaceCase> {};

TEST_P(Furnace, EveryPixelIsOneWithinThreeStandardErrors) {
  const FurnaceCase c = GetParam();
  Material m;
  m.model = c.model;
  m.base_color = Eigen::Vector3d::Ones();
  m.roughness = 0;
  m.ior = 1.5;
  loom::Environment env;
  if (c.map)
    env.map = test::constant_map(32, 16, 1.f);
  else
    env.color = Eigen::Vector3d::Ones();
  const loom::Scene scene = test::sphere_in_environment(m, env);
  RenderSettings s;
  s.width = s.height = 8;
  s.spp = 16;
  s.max_depth = 200;  // glass: a few internal reflections carry ~0.04^k of the light
  s.russian_roulette = c.roulette;
  s.rr_min_depth = 1;
  const auto stats = test::independent_renders(scene, s, 64);
  int outside = 0;
  double worst = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x)
      for (int ch = 0; ch < 3; ++ch) {
        const double mean = stats.mean.at<cv::Vec3d>(y, x)[ch];
        const double se = stats.standard_error.at<cv::Vec3d>(y, x)[ch];
        ASSERT_TRUE(std::isfinite(mean));
        const double z = std::abs(mean - 1) / (se + 1e-6);
        worst = std::max(worst, z);
        outside += std::abs(mean - 1) > 3 * se + 1e-5;
      }
  EXPECT_LE(outside, 3 * 2) << c.name << ": worst deviation " << worst << " standard errors";
  EXPECT_LT(worst, 4.5) << c.name;
  EXPECT_NEAR(cv::mean(stats.mean)[0], 1.0, 0.02) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Materials, Furnace,
    ::testing::Values(FurnaceCase{"diffuse_color", Material::Model::diffuse, false, false},
                      FurnaceCase{"diffuse_color_rr", Material::Model::diffuse, true, false},
                      FurnaceCase{"diffuse_map", Material::Model::diffuse, false, true},
                      FurnaceCase{"diffuse_map_rr", Material::Model::diffuse, true, true},
                      FurnaceCase{"mirror_map", Material::Model::conductor, false, true},
                      FurnaceCase{"mirror_map_rr", Material::Model::conductor, true, true},
                      FurnaceCase{"glass_map", Material::Model::dielectric, false, true},
                      FurnaceCase{"glass_map_rr", Material::Model::dielectric, true, true}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
