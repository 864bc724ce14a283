// Unidirectional path tracing with next-event estimation and multiple
// importance sampling (Veach 1997, ch. 9; pbrt-v4's PathIntegrator):
//   L = Le + Σ_paths β (NEE: f Le w_light / p_light + BSDF hit: Le w_bsdf),
//   w by the power heuristic between the light's and the BSDF's densities.
// A path has at most max_depth bounces: max_depth = 1 is direct light only
// (Embree's tutorial counts the same way: "1 = primary + shadow").
// Sample s of pixel p draws from PixelSampler(kind, seed, p, s) (owen_sobol.hpp),
// so the image does not depend on the thread count or on how samples are
// batched into passes.
#pragma once

#include <cstdint>
#include <functional>

#include <opencv2/core.hpp>

#include "embree_scene.hpp"
#include "environment_light.hpp"
#include "owen_sobol.hpp"
#include "loom/node.hpp"
#include "loom/scene.hpp"

namespace loom::pathtrace {

enum class Strategy { mis, nee, bsdf };

struct RenderSettings {
  int width = 512, height = 512;
  int spp = 64;
  int max_depth = 8;
  bool russian_roulette = true;
  int rr_min_depth = 3;  // bounces before roulette may end a path
  Strategy strategy = Strategy::mis;
  SamplerKind sampler = SamplerKind::sobol;
  EnvironmentLight::Sampling environment_sampling = EnvironmentLight::Sampling::importance;
  // Adaptive sampling: a pixel stops once the relative standard error of its
  // luminance mean falls below the threshold (0: off), after at least min spp.
  double adaptive_threshold = 0;
  int adaptive_min_spp = 16;
  std::uint64_t seed = 1;
  // The pixels to trace (Context::region()); the others stay black. Split by
  // samples: the samples this part takes, its sums added to the other parts'
  // by sum_over_parts after each pass (Context::sum_over_parts).
  PixelRegion region;
  std::function<void(double*, std::size_t, double)> sum_over_parts;
  // Dealt as parts ask (region.dealt()): the next slot of the pass for this
  // part, -1 once the pass is taken (Context::take_slot).
  std::function<int()> take_slot;
  // Without adaptive sampling: coarse passes (sample 0 of one pixel in 64,
  // 16, 4), then passes of 1, 1, 2, 4, … samples per pixel, so that the image so far
  // can be shown after each (RenderHooks::after_pass); off: one pass of spp.
  // Every pixel takes its own samples in order either way, so the final
  // image is the same bit for bit.
  bool progressive = false;
};

// The pixels' sums so far, between passes (integrator.cpp).
struct Film;
// The means so far, CV_32FC3; a pixel without samples shows the pixel at
// the corner of the smallest 2x2, 4x4 or 8x8 block that has one (after the
// coarse first passes).
cv::Mat mean_image(const Film& film);
// The estimated relative RMS error of the pixels' luminance means so far,
// from their sample variances; -1 while no pixel has two samples.
double relative_error(const Film& film);
// The samples per pixel so far, over the whole image.
double mean_samples(const Film& film);

// What render() reports while it runs; each hook may throw (loom::Cancelled)
// to stop it.
struct RenderHooks {
  // On the calling thread between batches of tiles: the fraction done.
  std::function<void(double)> progress;
  // On worker threads before every sample: cancellation lands within a
  // sample's time, however many samples a pass takes.
  std::function<void()> check_cancelled;
  // On the calling thread after each pass, the last one included (a viewer
  // then shows the whole image as soon as it is done, before the evaluation
  // ends): the film and the samples per pixel so far (1/64, 1/16, 1/4 after
  // the coarse passes).
  std::function<void(const Film&, double)> after_pass;
  // On the calling thread between batches of tiles inside a pass (a pass of
  // many samples takes seconds: a viewer may show the film as it fills).
  std::function<void(const Film&)> between_batches;
};

struct RenderResult {
  cv::Mat image;    // CV_32FC3 linear radiance
  cv::Mat albedo;   // CV_32FC3 first-hit base color (black where nothing is hit)
  cv::Mat normal;   // CV_32FC3 first-hit world shading normal (zero where nothing is hit)
  cv::Mat depth;    // CV_32FC1 first-hit distance along the ray (0 where nothing is hit)
  cv::Mat samples;  // CV_32FC1 samples taken per pixel
  double mean_spp = 0;
  double relative_error = -1;  // relative_error(film) at the end
  std::uint64_t paths = 0, rays = 0;  // rays: closest-hit and shadow rays traced
  std::uint64_t shadow_rays = 0;
  std::uint64_t nonfinite = 0;  // samples discarded because they were NaN or infinite
  std::size_t emissive_triangles = 0;
  bool environment_sampled = false;
};

RenderResult render(const Scene& scene, const Camera& camera, const EmbreeScene& traced,
                    const RenderSettings& settings, const RenderHooks& hooks = {});

}  // namespace loom::pathtrace
