// The scattering models against independent quadrature: the GGX
// distribution is normalized, each model's sampling weights average to the
// albedo computed by integrating eval over the sphere, sample() reports
// eval / pdf, and no model reflects more than it receives.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "bsdf.hpp"

namespace {

using namespace loom::pathtrace;
using Model = loom::Material::Model;

template <class F>
double integrate_sphere(F f, int n) {
  const double dt = M_PI / n, dp = M_PI / n;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double theta = (i + 0.5) * dt, phi = (j + 0.5) * dp;
      const Vec3f d(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                    float(std::cos(theta)));
      sum += f(d) * std::sin(theta) * dt * dp;
    }
  return sum;
}

TEST(Ggx, DistributionAndVisibleNormalsAreNormalized) {
  for (float alpha : {0.05f, 0.3f, 1.0f}) {
    const Ggx g{alpha};
    // ∫ D(h) cos θh dω = 1 (projected microfacet area).
    EXPECT_NEAR(integrate_sphere([&](const Vec3f& h) { return h.z() > 0 ? g.D(h) * h.z() : 0; }, 2000),
                1.0, 2e-3)
        << alpha;
    const Vec3f wo = Vec3f(0.6f, 0.1f, 0.5f).normalized();
    EXPECT_NEAR(integrate_sphere([&](const Vec3f& h) { return g.visible_pdf(wo, h); }, 2000), 1.0, 2e-3)
        << alpha;
  }
}

struct Case {
  Model model;
  float roughness;
};

class Bsdf : public ::testing::TestWithParam<Case> {};

TEST_P(Bsdf, SamplingAgreesWithQuadrature) {
  const Case c = GetParam();
  SurfaceMaterial m;
  m.model = c.model;
  m.base = Vec3f(0.9f, 0.7f, 0.4f);
  m.ggx.alpha = c.roughness * c.roughness;
  m.ior = 1.5f;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> uni(0, 1);
  for (const Vec3f& wo : {Vec3f(0.3f, 0.2f, 0.9f).normalized(), Vec3f(0.9f, 0.0f, 0.2f).normalized(),
                          Vec3f(-0.4f, 0.3f, -0.8f).normalized()}) {
    if (wo.z() < 0 && c.model != Model::dielectric) continue;
    // Albedo by quadrature of eval (independent of the sampling code)...
    const double albedo =
        integrate_sphere([&](const Vec3f& wi) { return double(bsdf_eval(m, wo, wi).x()); }, 1500);
    const double pdf_mass = integrate_sphere([&](const Vec3f& wi) { return double(bsdf_pdf(m, wo, wi)); }, 1500);
    // ... and by averaging the sampling weights.
    const int n = 400000;
    double mean = 0, mean2 = 0;
    for (int i = 0; i < n; ++i) {
      const float uc = uni(rng);
      const auto s = bsdf_sample(m, wo, uc, Vec2f(uni(rng), uni(rng)));
      if (!s) continue;
      ASSERT_TRUE(s->weight.allFinite());
      ASSERT_FALSE(s->delta);
      ASSERT_NEAR(s->pdf, bsdf_pdf(m, wo, s->wi), 1e-3f * s->pdf + 1e-6f);
      const Vec3f f = bsdf_eval(m, wo, s->wi);
      ASSERT_NEAR(s->weight.x(), f.x() / s->pdf, 1e-3f * s->weight.x() + 1e-6f);
      mean += s->weight.x() / n;
      mean2 += double(s->weight.x()) * s->weight.x() / n;
    }
    const double se = std::sqrt(std::max(0.0, mean2 - mean * mean) / n);
    EXPECT_NEAR(mean, albedo, 4 * se + 2e-3) << int(c.model) << " roughness " << c.roughness;
    // Radiance leaving glass grows by eta² (it is compressed into a smaller
    // solid angle), so only light arriving from outside is bounded by 1.
    if (wo.z() > 0) {
      EXPECT_LE(albedo, 1.0 + 2e-3) << int(c.model);
    }
    EXPECT_LE(pdf_mass, 1.0 + 2e-3);
  }
}

INSTANTIATE_TEST_SUITE_P(Models, Bsdf,
                         ::testing::Values(Case{Model::diffuse, 0.5f}, Case{Model::conductor, 0.3f},
                                           Case{Model::conductor, 1.0f}, Case{Model::plastic, 0.4f},
                                           Case{Model::plastic, 1.0f}, Case{Model::dielectric, 0.3f},
                                           Case{Model::dielectric, 0.8f}));

TEST(Bsdf, SmoothModelsAreDeltaLobes) {
  SurfaceMaterial m;
  m.ggx.alpha = 0;
  const Vec3f wo = Vec3f(0.3f, 0.4f, 0.8f).normalized();
  m.model = Model::conductor;
  m.base = Vec3f::Ones();
  auto s = bsdf_sample(m, wo, 0.5f, Vec2f(0.3f, 0.7f));
  ASSERT_TRUE(s && s->delta);
  EXPECT_NEAR((s->wi - Vec3f(-wo.x(), -wo.y(), wo.z())).norm(), 0, 1e-6);
  EXPECT_NEAR(s->weight.x(), 1, 1e-6);
  m.model = Model::dielectric;
  // Snell: sin θt = sin θi / 1.5 on the transmitted branch.
  s = bsdf_sample(m, wo, 0.99f, Vec2f(0.3f, 0.7f));
  ASSERT_TRUE(s && s->delta);
  const float sin_i = std::sqrt(1 - wo.z() * wo.z()), sin_t = std::sqrt(1 - s->wi.z() * s->wi.z());
  EXPECT_NEAR(sin_t, sin_i / 1.5f, 1e-5);
  EXPECT_LT(s->wi.z(), 0);
  EXPECT_EQ(bsdf_eval(m, wo, s->wi), Vec3f::Zero());
}

// The inline cos/sin of the sampling warps against libm in double, over a
// fine sweep of [0, 1) including the quadrant boundaries and the largest
// float below 1; the inline 1/sqrt against sqrt in double.
TEST(Sampling, CosSinAndInverseSqrtMatchLibm) {
  double worst = 0;
  std::vector<float> ts;
  for (int i = 0; i < 200000; ++i) ts.push_back(float(i) / 200000);
  for (float q : {0.125f, 0.25f, 0.375f, 0.5f, 0.625f, 0.75f, 0.875f}) {
    ts.push_back(std::nextafter(q, 0.f));
    ts.push_back(std::nextafter(q, 1.f));
  }
  ts.push_back(0x1.fffffep-1f);
  for (float t : ts) {
    float c = 0, s = 0;
    cos_sin_2pi(t, &c, &s);
    const double phi = 2 * M_PI * double(t);
    worst = std::max({worst, std::abs(c - std::cos(phi)), std::abs(s - std::sin(phi))});
  }
  EXPECT_LT(worst, 2e-7);
  // The reciprocal square root of unit(), point lights and shadow rays, over
  // twelve decades.
  double worst_rsqrt = 0;
  for (double x = 1e-6; x < 1e6; x *= 1.0007) {
    const float xf = float(x);
    worst_rsqrt = std::max(worst_rsqrt, std::abs(inv_sqrt(xf) * std::sqrt(double(xf)) - 1));
  }
  EXPECT_LT(worst_rsqrt, 5e-7);
  // The warps stay unit length.
  for (float t : {0.f, 0.1f, 0.3f, 0.6f, 0.9f})
    EXPECT_NEAR(sample_cosine_hemisphere(Vec2f(0.37f, t)).norm(), 1, 1e-6);
}

}  // namespace
