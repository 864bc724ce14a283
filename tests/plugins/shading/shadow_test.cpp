// Shadow maps against exact visibility: each visible pixel's world position
// ray-cast to the light with Embree. Target: at most 1% misclassified pixels
// at a 2048² map with the default bias and slope bias, excluding a one-pixel
// band at the exact shadow's edges.
#include <gtest/gtest.h>

#include "exact_shadows.hpp"
#include "rasterizer.hpp"
#include "shading_scenes.hpp"

namespace loom::shading {
namespace {

Rasterizer& rasterizer() {
  static Rasterizer r;
  return r;
}

exact::ShadowComparison misclassified(Light::Kind kind, ShadowFilter filter, const RenderOptions& base = {},
                                      int width = 480, int height = 320) {
  const Scene scene = scenes::shadow_scene(kind);
  RenderOptions o = base;
  o.width = width;
  o.height = height;
  o.samples = 1;  // every pixel one surface point: the exact reference's
  o.aux = true;
  o.shadows = filter;
  const RenderImages r = rasterizer().render(scene, o);
  const cv::Mat truth = exact::exact_visibility(scene, scene.lights[0], r.position, r.normal);
  return exact::compare_shadows(truth, r.shadow);
}

TEST(ShadowMaps, DefaultBiasIsWithinOnePercentOfExactVisibility) {
  for (Light::Kind kind : {Light::Kind::directional, Light::Kind::spot, Light::Kind::point})
    for (ShadowFilter filter : {ShadowFilter::hard, ShadowFilter::pcf}) {
      // 960x640: a pixel is about one 2048 texel of floor, so texel-sized
      // errors are not hidden inside the excluded edge band.
      const auto c = misclassified(kind, filter, {}, 960, 640);
      EXPECT_GT(c.compared, 200000);
      EXPECT_LE(c.rate(), 0.01) << "light " << int(kind) << " filter " << int(filter) << ": " << c.wrong
                                << " of " << c.compared;
    }
}

TEST(ShadowMaps, NoBiasShowsAcne) {
  RenderOptions o;
  o.shadow_bias = 0;
  o.shadow_slope_bias = 0;
  const auto none = misclassified(Light::Kind::directional, ShadowFilter::hard, o);
  const auto ok = misclassified(Light::Kind::directional, ShadowFilter::hard);
  EXPECT_GT(none.rate(), 5 * ok.rate() + 0.01) << none.rate() << " vs " << ok.rate();
}

TEST(ShadowMaps, HugeBiasPetersPans) {
  RenderOptions o;
  o.shadow_bias = 300;  // 1.2 scene units: shadows detach from their casters
  const auto c = misclassified(Light::Kind::directional, ShadowFilter::hard, o);
  EXPECT_GT(c.rate(), 0.01);
}

TEST(ShadowMaps, OffMeansEverythingLit) {
  const Scene scene = scenes::shadow_scene(Light::Kind::spot);
  RenderOptions o;
  o.width = 64;
  o.height = 48;
  o.aux = true;
  o.shadows = ShadowFilter::off;
  const RenderImages r = rasterizer().render(scene, o);
  double lo, hi;
  cv::minMaxLoc(r.shadow, &lo, &hi);
  EXPECT_EQ(lo, 1.0);
}

}  // namespace
}  // namespace loom::shading
