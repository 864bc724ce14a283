// The environment map's density (eq. 64): it integrates to 1 over the sphere,
// sample() draws directions by it (chi-square against the histogram), and it
// is what sample() reports.
#include <gtest/gtest.h>

#include <random>

#include "environment_light.hpp"
#include "test_scenes.hpp"

namespace {

using namespace loom::pathtrace;

std::shared_ptr<loom::Image> random_map(int w, int h, bool bright_pixel) {
  cv::Mat m(h, w, CV_32FC3);
  cv::RNG rng(3);
  rng.fill(m, cv::RNG::UNIFORM, 0.0, 1.0);
  if (bright_pixel) m.at<cv::Vec3f>(h / 3, w / 5) = cv::Vec3f(5000, 4000, 3000);
  return std::make_shared<loom::Image>(m, loom::Encoding::linear);
}

// ∫ f(ω) dω over the sphere by the midpoint rule on an (n x 2n) grid in (θ, φ).
template <class F>
double integrate_sphere(F f, int n, double theta0 = 0, double theta1 = M_PI, double phi0 = -M_PI,
                        double phi1 = M_PI) {
  const double dt = (theta1 - theta0) / n, dp = (phi1 - phi0) / (2 * n);
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double theta = theta0 + (i + 0.5) * dt, phi = phi0 + (j + 0.5) * dp;
      const Vec3f d(float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)),
                    float(-std::sin(theta) * std::cos(phi)));
      sum += f(d) * std::sin(theta) * dt * dp;
    }
  return sum;
}

class EnvironmentPdf : public ::testing::TestWithParam<bool> {};

TEST_P(EnvironmentPdf, IntegratesToOne) {
  loom::Environment env;
  env.map = random_map(64, 32, GetParam());
  env.rotation = 0.7;
  for (auto mode : {EnvironmentLight::Sampling::importance, EnvironmentLight::Sampling::uniform}) {
    const EnvironmentLight light(env, mode);
    EXPECT_NEAR(integrate_sphere([&](const Vec3f& d) { return light.pdf(d); }, 1024), 1.0, 1e-3);
  }
}

TEST_P(EnvironmentPdf, SamplesFollowTheDensity) {
  loom::Environment env;
  env.map = random_map(64, 32, GetParam());
  const EnvironmentLight light(env, EnvironmentLight::Sampling::importance);
  // Bins: 8 bands of θ x 16 of φ = atan2(x, -z), each 4 x 4 map pixels, so the
  // midpoint rule over pdf(ω) sin θ dθ dφ is exact (eq. 64 makes pdf · sin θ
  // constant over a pixel); what this checks is the sampler against eq. 64.
  const int bt = 8, bp = 16, n = 1000000;
  std::vector<double> count(bt * bp, 0);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uni(0, 1);
  for (int i = 0; i < n; ++i) {
    const auto s = light.sample(uni(rng), Vec2f(uni(rng), uni(rng)));
    ASSERT_NEAR(s.pdf, light.pdf(s.direction), 1e-3f * s.pdf);
    const double theta = std::acos(std::clamp(double(s.direction.y()), -1.0, 1.0));
    const double phi = std::atan2(double(s.direction.x()), -double(s.direction.z()));
    const int a = std::min(bt - 1, int(theta / M_PI * bt));
    const int b = std::min(bp - 1, int((phi + M_PI) / (2 * M_PI) * bp));
    ++count[a * bp + b];
  }
  double chi2 = 0;
  int dof = -1;
  double pooled_count = 0, pooled_expected = 0;
  for (int a = 0; a < bt; ++a)
    for (int b = 0; b < bp; ++b) {
      const double p = integrate_sphere([&](const Vec3f& d) { return light.pdf(d); }, 64,
                                        M_PI * a / bt, M_PI * (a + 1) / bt,
                                        -M_PI + 2 * M_PI * b / bp, -M_PI + 2 * M_PI * (b + 1) / bp);
      const double expected = p * n;
      if (expected < 20) {  // pooled, as the test's validity asks
        pooled_count += count[a * bp + b];
        pooled_expected += expected;
        continue;
      }
      chi2 += (count[a * bp + b] - expected) * (count[a * bp + b] - expected) / expected;
      ++dof;
    }
  if (pooled_expected >= 20) {
    chi2 += (pooled_count - pooled_expected) * (pooled_count - pooled_expected) / pooled_expected;
    ++dof;
  }
  // A 1e-5 significance level: dof + 4.5 sqrt(2 dof) bounds its quantile for dof ~ 100.
  EXPECT_LT(chi2, dof + 4.5 * std::sqrt(2.0 * dof)) << "dof " << dof;
}

INSTANTIATE_TEST_SUITE_P(Maps, EnvironmentPdf, ::testing::Values(false, true));

TEST(EnvironmentLight, RadianceFollowsTheLatLongConvention) {
  // Straight up is the top row, -z the middle column (loom::latlong_uv).
  cv::Mat m(4, 8, CV_32FC3, cv::Scalar::all(0));
  m.at<cv::Vec3f>(0, 3) = cv::Vec3f(1, 2, 3);
  m.at<cv::Vec3f>(1, 4) = cv::Vec3f(7, 7, 7);  // theta 84°: v = 0.47
  loom::Environment env;
  env.map = std::make_shared<loom::Image>(m, loom::Encoding::linear);
  env.intensity = 2;
  const EnvironmentLight light(env, EnvironmentLight::Sampling::importance);
  EXPECT_FLOAT_EQ(light.radiance(Vec3f(0, 0.1f, -1).normalized()).x(), 14);
  EXPECT_FLOAT_EQ(light.radiance(Vec3f(-0.01f, 1, -0.01f).normalized()).z(), 6);
}

}  // namespace
