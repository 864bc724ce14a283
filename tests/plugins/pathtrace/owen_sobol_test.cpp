// The Owen-scrambled Sobol sampler (owen_sobol.hpp): its stratification
// (every aligned block of 2^k samples of a pixel is a (0,k,2)-net, counted
// cell by cell), the uniformity of one sample over pixels (chi-square), and
// rendering with it: the same image mean as the independent sampler within
// noise and a lower error per sample against an independent reference. (The
// same image at 1 and 2 threads and across adaptive passes: robustness_test,
// which runs with this sampler, the default.)
#include <gtest/gtest.h>

#include <vector>

#include "cornell_box_scene.hpp"
#include "owen_sobol.hpp"
#include "test_scenes.hpp"

namespace {

using namespace loom::pathtrace;

// Whether points [first, first + 2^k) of dimension pair d of one pixel put
// exactly one point in each of the 2^k cells of every elementary interval
// shape 2^-a × 2^-(k-a).
bool is_net(std::uint64_t pixel_key, std::uint32_t d, std::uint32_t first, int k) {
  const std::uint32_t n = 1u << k;
  for (int a = 0; a <= k; ++a) {
    std::vector<int> count(n, 0);
    for (std::uint32_t s = first; s < first + n; ++s) {
      const Fractions2 f = owen_sobol_2d(pixel_key, d, s);
      const std::uint32_t cx = a == 0 ? 0 : f.x >> (32 - a), cy = a == k ? 0 : f.y >> (32 - (k - a));
      ++count[(cx << (k - a)) | cy];
    }
    for (int c : count)
      if (c != 1) return false;
  }
  return true;
}

TEST(OwenSobol, EveryAlignedBlockOfTwoToTheKSamplesIsANet) {
  for (std::uint64_t key : {1ull, 0x1234567ull, 0xdeadbeefcafeull})
    for (std::uint32_t d : {0u, 1u, 7u, 40u})
      for (int k = 0; k <= 10; ++k) {
        EXPECT_TRUE(is_net(key, d, 0, k)) << "key " << key << " pair " << d << " k " << k;
        EXPECT_TRUE(is_net(key, d, 3u << k, k)) << "block 3, key " << key << " pair " << d << " k " << k;
      }
}

TEST(OwenSobol, IndependentPairsAreNotTheSamePoints) {
  int same = 0;
  for (std::uint32_t s = 0; s < 64; ++s) same += owen_sobol_2d(9, 0, s).x == owen_sobol_2d(9, 1, s).x;
  EXPECT_LT(same, 4);
}

// Bit j of the Laine-Karras permutation depends on input bits 0..j only (what
// makes it an Owen scramble of the reversed fraction), and it is a bijection.
TEST(OwenSobol, LaineKarrasBitsDependOnLowerBitsOnly) {
  for (std::uint32_t x : {0u, 1u, 0x89abcdefu, 0xffffffffu})
    for (int j = 0; j < 32; ++j) {
      const std::uint32_t a = laine_karras_permutation(x, 0x5eed), b = laine_karras_permutation(x ^ (1u << j), 0x5eed);
      const std::uint32_t below = j == 0 ? 0u : (1u << j) - 1;
      EXPECT_EQ(a & below, b & below);
      EXPECT_NE(a & (1u << j), b & (1u << j));
    }
  EXPECT_EQ(reverse_bits(1u), 0x80000000u);
  EXPECT_EQ(reverse_bits(0x12345678u), 0x1e6a2c48u);
}

// One sample index over 2^16 pixels: uniform over the unit square (64×64
// cells, chi-square below dof + 4.5 √(2 dof)), for a pair computed when the
// bounce starts (light) and one drawn when asked for (lobe and roulette).
TEST(OwenSobol, OneSampleIsUniformOverPixels) {
  for (std::uint32_t s : {0u, 5u, 1000u})
    for (const bool prepared : {true, false}) {
      std::vector<int> count(64 * 64, 0);
      const int n = 1 << 16;
      for (int p = 0; p < n; ++p) {
        PixelSampler sampler(SamplerKind::sobol, 3, std::uint64_t(p), s);
        sampler.start_bounce(2, true);
        const Vec2f u = prepared ? sampler.uniform2(Decision::light)
                                 : Vec2f(sampler.uniform(Decision::lobe), sampler.uniform(Decision::roulette));
        ++count[int(u.y() * 64) * 64 + int(u.x() * 64)];
      }
      const double expected = double(n) / count.size();
      double chi2 = 0;
      for (int c : count) chi2 += (c - expected) * (c - expected) / expected;
      const double dof = double(count.size()) - 1;
      EXPECT_LT(chi2, dof + 4.5 * std::sqrt(2 * dof)) << "sample " << s << (prepared ? " light" : " lobe, roulette");
    }
}

// A decision's numbers do not depend on which other decisions a bounce drew
// (a glossy hit draws a lobe before its direction, a diffuse one does not).
TEST(OwenSobol, EachDecisionHasItsOwnPair) {
  for (std::uint64_t p : {0ull, 17ull, 40000ull})
    for (std::uint64_t s : {0ull, 3ull, 250ull}) {
      PixelSampler a(SamplerKind::sobol, 9, p, s), b(SamplerKind::sobol, 9, p, s);
      a.start_bounce(1, true);
      b.start_bounce(1, false);
      b.uniform(Decision::lobe);
      b.uniform2(Decision::light);
      EXPECT_EQ(a.uniform2(Decision::direction), b.uniform2(Decision::direction));
      EXPECT_EQ(a.uniform(Decision::roulette), b.uniform(Decision::roulette));
    }
}

double mean_squared_error(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const cv::Mat squared = d.mul(d);
  return cv::mean(squared.reshape(1))[0];
}

// Unbiased: the Cornell box's image mean with Sobol points equals the
// independent sampler's (the estimator the furnace and strategy tests
// established) within 3 combined standard errors; and it has less error per
// sample against a reference rendered with the independent sampler.
TEST(OwenSobol, SameMeanAsIndependentSamplingAndLessError) {
  const loom::Scene scene = cornell_box(CornellBoxOptions{});
  const EmbreeScene traced(scene);
  RenderSettings s;
  s.width = s.height = 16;
  s.spp = 16;
  s.max_depth = 4;
  s.sampler = SamplerKind::independent;
  const test::MeanAndError independent = test::image_mean(scene, s, 30, 77);
  s.sampler = SamplerKind::sobol;
  const test::MeanAndError sobol = test::image_mean(scene, s, 30, 77);
  EXPECT_LT(std::abs(sobol.mean - independent.mean), 3 * std::hypot(sobol.se, independent.se))
      << sobol.mean << " ± " << sobol.se << " vs " << independent.mean << " ± " << independent.se;

  RenderSettings r = s;
  r.sampler = SamplerKind::independent;
  r.spp = 4096;
  r.seed = 5;
  const cv::Mat reference = render(scene, *scene.camera, traced, r).image;
  double mse[2] = {0, 0};
  for (int k = 0; k < 4; ++k) {
    s.seed = 900 + std::uint64_t(k);
    s.sampler = SamplerKind::sobol;
    mse[0] += mean_squared_error(render(scene, *scene.camera, traced, s).image, reference);
    s.sampler = SamplerKind::independent;
    mse[1] += mean_squared_error(render(scene, *scene.camera, traced, s).image, reference);
  }
  EXPECT_LT(mse[0], 0.8 * mse[1]) << "sobol " << mse[0] / 4 << " independent " << mse[1] / 4;
}

}  // namespace
