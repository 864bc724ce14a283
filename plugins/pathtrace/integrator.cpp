#include "integrator.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "camera_rays.hpp"
#include "light_sampler.hpp"
#include "owen_sobol.hpp"
#include "path_loop.hpp"

namespace loom::pathtrace {

struct PixelAccumulator {
  double L[3] = {0, 0, 0};
  double albedo[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
  double depth = 0, lum = 0, lum2 = 0;
  int n = 0;
  bool done = false;

  void add(const PathResult& p) {
    const float l = luminance(p.L);
    for (int i = 0; i < 3; ++i) {
      L[i] += p.L[i];
      albedo[i] += p.albedo[i];
      normal[i] += p.normal[i];
    }
    depth += p.depth;
    lum += l;
    lum2 += double(l) * l;
  }
};

// The image's pixels and what one pass over them needs.
struct Film {
  int width, height;
  std::vector<PixelAccumulator> pixels;
  static constexpr int kTile = 16;
  int tiles_x, tiles;
  Film(int w, int h)
      : width(w),
        height(h),
        pixels(std::size_t(w) * h),
        tiles_x((w + kTile - 1) / kTile),
        tiles(tiles_x * ((h + kTile - 1) / kTile)) {}
};

namespace {

struct RayCounts {
  std::uint64_t rays = 0, shadow_rays = 0, nonfinite = 0;
  void operator+=(const RayCounts& o) {
    rays += o.rays;
    shadow_rays += o.shadow_rays;
    nonfinite += o.nonfinite;
  }
};
// The same, summed over the threads of a render.
struct SharedRayCounts {
  std::atomic<std::uint64_t> rays{0}, shadow_rays{0}, nonfinite{0};
  void operator+=(const RayCounts& o) {
    rays += o.rays;
    shadow_rays += o.shadow_rays;
    nonfinite += o.nonfinite;
  }
};

// What one pass takes: every pixel that is not done is brought up to `target`
// samples; with stride k only the pixels whose x and y are multiples of k
// (the coarse first passes, one pixel in k², shown as blocks).
struct Pass {
  int target = 0;
  int stride = 1;
};

// Sample `sample` of pixel (x, y), added to its sums.
void trace_sample(const PathContext& c, const CameraRays& cam, Film& film, int x, int y, int sample,
                  RayCounts& counts) {
  const std::size_t index = std::size_t(y) * film.width + x;
  Vec3f origin, dir;
  PixelSampler sampler = start_sample(c, cam, film.width, film.height, index, sample, origin, dir);
  const PathResult p = trace_path(c, origin, dir, sampler);
  counts.rays += std::uint64_t(p.rays + p.shadow_rays);
  counts.shadow_rays += std::uint64_t(p.shadow_rays);
  PixelAccumulator& a = film.pixels[index];
  ++a.n;
  if (!p.L.allFinite()) {
    ++counts.nonfinite;  // counted as a black sample: the mean stays finite
    return;
  }
  a.add(p);
}

bool in_pass(const PixelAccumulator& a, int x, int y, Pass pass) {
  return !a.done && x % pass.stride == 0 && y % pass.stride == 0;
}

RayCounts trace_tile(const PathContext& c, const CameraRays& cam, Film& film, int tile, Pass pass,
                     const std::function<void()>& check_cancelled) {
  RayCounts counts;
  const int W = film.width, H = film.height;
  const int x0 = (tile % film.tiles_x) * Film::kTile, y0 = (tile / film.tiles_x) * Film::kTile;
  for (int y = y0; y < std::min(H, y0 + Film::kTile); ++y)
    for (int x = x0; x < std::min(W, x0 + Film::kTile); ++x) {
      const PixelAccumulator& a = film.pixels[std::size_t(y) * W + x];
      if (!in_pass(a, x, y, pass) || !c.settings.region.contains(x, y, W)) continue;
      for (int sample = a.n; sample < pass.target; ++sample) {
        if (!c.settings.region.takes_sample(sample)) continue;
        if (check_cancelled) check_cancelled();  // a sample's time at most: cancel lands fast
        trace_sample(c, cam, film, x, y, sample, counts);
      }
    }
  return counts;
}

// One pass of `pass` samples per active pixel, in batches of tiles with
// progress on the calling thread between batches; cancellation is checked
// before every sample, on the workers.
void trace_pass(const PathContext& c, const CameraRays& cam, Film& film, Pass pass, SharedRayCounts& counts,
                const RenderHooks& hooks) {
  const double total = double(film.width) * film.height * c.settings.spp;
  constexpr int kBatch = 32;  // tiles between progress reports
  for (int first = 0; first < film.tiles; first += kBatch) {
    const int last = std::min(film.tiles, first + kBatch);
    tbb::parallel_for(tbb::blocked_range<int>(first, last, 1), [&](const tbb::blocked_range<int>& range) {
      RayCounts sum;
      for (int tile = range.begin(); tile != range.end(); ++tile)
        sum += trace_tile(c, cam, film, tile, pass, hooks.check_cancelled);
      counts += sum;
    });
    if (hooks.progress) {
      double done = 0;
      for (const auto& a : film.pixels) done += a.n;
      hooks.progress(std::min(1.0, done / total));
    }
    if (hooks.between_batches && last < film.tiles) hooks.between_batches(film);
  }
}

// Dealt as parts ask (PixelRegion::dealt): the pixels grouped by
// spread(p) % slots, so that a slot's samples are found without looking at
// every pixel.
std::vector<std::vector<std::uint32_t>> pixels_by_spread(const Film& film, const PixelRegion& region) {
  std::vector<std::vector<std::uint32_t>> groups(std::size_t(region.slots));
  for (std::size_t p = 0; p < film.pixels.size(); ++p)
    groups[std::size_t(region.slot_of(p, 0))].push_back(std::uint32_t(p));
  return groups;
}

// A pass dealt as parts ask: this part takes slots (Context::take_slot)
// until none is left and traces, for each, the samples s of each active
// pixel p with (s + spread(p)) % slots == slot, from the pixel's count when
// the pass began (`first`, every part's samples) to the pass's target. For
// each of the pass's first `slots` sample numbers s0, the pixels of one
// spread group take s0, s0 + slots, ...: each pixel once per slot, so the
// slot's pixels are traced in parallel.
void trace_dealt_pass(const PathContext& c, const CameraRays& cam, Film& film, Pass pass,
                      const std::vector<std::vector<std::uint32_t>>& groups, SharedRayCounts& counts,
                      const RenderHooks& hooks) {
  const int W = film.width, slots = c.settings.region.slots;
  std::vector<int> first(film.pixels.size());
  int lowest = pass.target;
  double before = 0, in_this_pass = 0;  // samples, for progress
  for (std::size_t p = 0; p < first.size(); ++p) {
    first[p] = film.pixels[p].n;
    before += first[p];
    if (!in_pass(film.pixels[p], int(p % std::size_t(W)), int(p / std::size_t(W)), pass)) continue;
    lowest = std::min(lowest, first[p]);
    in_this_pass += std::max(0, pass.target - first[p]);
  }
  const double total = double(film.width) * film.height * c.settings.spp;
  std::vector<std::pair<std::uint32_t, int>> work;  // a slot's pixels, each with its lowest sample
  for (int slot; (slot = c.settings.take_slot()) >= 0;) {
    work.clear();
    for (int s0 = lowest; s0 < std::min(pass.target, lowest + slots); ++s0)
      for (std::uint32_t p : groups[std::size_t(((slot - s0) % slots + slots) % slots)])
        if (in_pass(film.pixels[p], int(p % std::uint32_t(W)), int(p / std::uint32_t(W)), pass))
          work.emplace_back(p, s0 + (std::max(0, first[p] - s0) + slots - 1) / slots * slots);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, work.size(), 16), [&](const auto& range) {
      RayCounts sum;
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const auto [p, lowest_sample] = work[i];
        for (int sample = lowest_sample; sample < pass.target; sample += slots) {
          if (hooks.check_cancelled) hooks.check_cancelled();
          trace_sample(c, cam, film, int(p % std::uint32_t(W)), int(p / std::uint32_t(W)), sample, sum);
        }
      }
      counts += sum;
    });
    // The slots are taken in order over all parts: slot + 1 of them are dealt.
    if (hooks.progress) hooks.progress(std::min(1.0, (before + in_this_pass * (slot + 1) / slots) / total));
    if (hooks.between_batches) hooks.between_batches(film);
  }
}

// Samples per active pixel in the next pass. Adaptive sampling:
// adaptive_min_spp first, then a quarter more each pass. Otherwise all at
// once, or progressively 1, 1, 2, 4, … (the total doubling) so that the
// image can be shown after each pass. Sample s of a pixel is the same
// whatever pass takes it (PixelSampler(seed, pixel, s)) and is added in the
// same order, so every schedule ends with the same image, bit for bit.
int next_pass(const RenderSettings& s, int taken) {
  if (!(s.adaptive_threshold > 0)) return s.progressive ? std::min(s.spp - taken, std::max(1, taken)) : s.spp - taken;
  if (taken == 0) return std::min(s.spp, std::max(1, s.adaptive_min_spp));
  return std::min(s.spp - taken, std::max(4, taken / 4));
}

// Adaptive sampling: a pixel is done when the relative standard error of its
// luminance mean is below the threshold (with a floor for black pixels).
void mark_converged(Film& film, double threshold) {
  for (auto& a : film.pixels) {
    if (a.done || a.n < 2) continue;
    const double mean = a.lum / a.n;
    const double var = std::max(0.0, (a.lum2 - a.lum * mean) / (a.n - 1));
    a.done = std::sqrt(var / a.n) < threshold * std::max(mean, 1e-3);
  }
}

// A pixel's sums as doubles: L, albedo, normal (3 each), depth, lum, lum2, n.
constexpr std::size_t kSums = 13;
void read_sums(const PixelAccumulator& a, double* out) {
  for (int i = 0; i < 3; ++i) {
    out[i] = a.L[i];
    out[3 + i] = a.albedo[i];
    out[6 + i] = a.normal[i];
  }
  out[9] = a.depth;
  out[10] = a.lum;
  out[11] = a.lum2;
  out[12] = a.n;
}
void write_sums(const double* in, PixelAccumulator& a) {
  for (int i = 0; i < 3; ++i) {
    a.L[i] = in[i];
    a.albedo[i] = in[3 + i];
    a.normal[i] = in[6 + i];
  }
  a.depth = in[9];
  a.lum = in[10];
  a.lum2 = in[11];
  a.n = int(in[12]);
}

// Split by samples: each part traced its share of a pass; what the pass added
// on every part is summed, so that every part holds the sums of every sample
// so far (`total`, kSums per pixel) and decides convergence from them. The
// samples this part took in the pass go with it, for the engine's report.
void sum_pass_over_parts(Film& film, std::vector<double>& total,
                         const std::function<void(double*, std::size_t, double)>& sum_over_parts) {
  std::vector<double> pass(total.size());
  double taken = 0;  // the pass's added counts, the last of each pixel's sums
  for (std::size_t p = 0; p < film.pixels.size(); ++p) {
    read_sums(film.pixels[p], &pass[p * kSums]);
    for (std::size_t i = p * kSums; i < (p + 1) * kSums; ++i) pass[i] -= total[i];
    taken += pass[p * kSums + kSums - 1];
  }
  sum_over_parts(pass.data(), pass.size(), taken);
  for (std::size_t p = 0; p < film.pixels.size(); ++p) {
    for (std::size_t i = p * kSums; i < (p + 1) * kSums; ++i) total[i] += pass[i];
    write_sums(&total[p * kSums], film.pixels[p]);
  }
}

// The pixels' means as images.
void resolve(const Film& film, RenderResult& out) {
  const int W = film.width, H = film.height;
  out.image.create(H, W, CV_32FC3);
  out.albedo.create(H, W, CV_32FC3);
  out.normal.create(H, W, CV_32FC3);
  out.depth.create(H, W, CV_32FC1);
  out.samples.create(H, W, CV_32FC1);
  double sum_n = 0;
  std::uint64_t paths = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const PixelAccumulator& a = film.pixels[std::size_t(y) * W + x];
      const double inv = a.n > 0 ? 1.0 / a.n : 0;
      for (int i = 0; i < 3; ++i) {
        out.image.at<cv::Vec3f>(y, x)[i] = float(a.L[i] * inv);
        out.albedo.at<cv::Vec3f>(y, x)[i] = float(a.albedo[i] * inv);
        out.normal.at<cv::Vec3f>(y, x)[i] = float(a.normal[i] * inv);
      }
      out.depth.at<float>(y, x) = float(a.depth * inv);
      out.samples.at<float>(y, x) = float(a.n);
      sum_n += a.n;
      paths += std::uint64_t(a.n);
    }
  out.mean_spp = sum_n / (double(W) * H);
  out.paths = paths;
}

}  // namespace

RenderResult render(const Scene& scene, const Camera& camera, const EmbreeScene& traced, const RenderSettings& s,
                    const RenderHooks& hooks) {
  const PathScene path_scene(scene, traced, s.environment_sampling);
  const PathContext context = path_scene.context(s);
  const CameraRays cam(camera, s.width, s.height);

  Film film(s.width, s.height);
  SharedRayCounts counts;
  std::vector<double> total(s.sum_over_parts ? film.pixels.size() * kSums : 0);  // split by samples: every part's sums
  auto end_pass = [&](double spp_so_far) {
    if (s.sum_over_parts) sum_pass_over_parts(film, total, s.sum_over_parts);
    if (hooks.after_pass) hooks.after_pass(film, spp_so_far);
  };
  const auto groups = s.region.dealt() ? pixels_by_spread(film, s.region) : std::vector<std::vector<std::uint32_t>>{};
  auto trace = [&](Pass pass) {
    if (s.region.dealt())
      trace_dealt_pass(context, cam, film, pass, groups, counts, hooks);
    else
      trace_pass(context, cam, film, pass, counts, hooks);
  };
  // Progressive: first sample 0 of one pixel in 8², 4², 2² (coarse images in
  // a 64th, 16th and 4th of a pass's time, as Cycles' viewport starts at a
  // low resolution), then every pixel takes its own samples in order as always.
  if (s.progressive && !(s.adaptive_threshold > 0))
    for (int stride : {8, 4, 2}) {
      trace({1, stride});
      end_pass(1.0 / (stride * stride));
    }
  // Convergence is decided after whole passes only, on every part from the
  // sums of every part, so every pixel takes the samples one process takes.
  for (int taken = 0; taken < s.spp;) {
    taken += next_pass(s, taken);
    trace({taken, 1});
    end_pass(taken);
    if (s.adaptive_threshold > 0 && taken < s.spp) mark_converged(film, s.adaptive_threshold);
  }
  RenderResult out;
  resolve(film, out);
  out.relative_error = relative_error(film);
  out.rays = counts.rays;
  out.shadow_rays = counts.shadow_rays;
  out.nonfinite = counts.nonfinite;
  out.emissive_triangles = path_scene.lights.emissive_triangles();
  out.environment_sampled = path_scene.lights.samples_environment();
  return out;
}

cv::Mat mean_image(const Film& film) {
  cv::Mat image(film.height, film.width, CV_32FC3);
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      const PixelAccumulator* p = &film.pixels[std::size_t(y) * film.width + x];
      for (int block = 2; p->n == 0 && block <= 8; block *= 2)  // after the coarse passes: the block's corner
        p = &film.pixels[std::size_t(y - y % block) * film.width + (x - x % block)];
      const PixelAccumulator& a = *p;
      const double inv = a.n > 0 ? 1.0 / a.n : 0;
      for (int i = 0; i < 3; ++i) image.at<cv::Vec3f>(y, x)[i] = float(a.L[i] * inv);
    }
  return image;
}

double mean_samples(const Film& film) {
  double n = 0;
  for (const PixelAccumulator& a : film.pixels) n += a.n;
  return film.pixels.empty() ? 0 : n / double(film.pixels.size());
}

// The relative RMS error of the pixels' luminance means, estimated from
// their sample variances s² (the adaptive sampler's): the standard error of a
// mean of n samples is s/√n, so  e = √(mean_p s_p²/n_p) / mean_p μ_p.
// It falls as 1/√spp; -1 while no pixel has two samples.
double relative_error(const Film& film) {
  double variance_of_means = 0, mean = 0;
  std::size_t counted = 0;
  for (const PixelAccumulator& a : film.pixels) {
    if (a.n < 2) continue;
    const double mu = a.lum / a.n;
    variance_of_means += std::max(0.0, (a.lum2 - a.lum * mu) / (a.n - 1)) / a.n;
    mean += mu;
    ++counted;
  }
  if (counted == 0 || !(mean > 0)) return -1;
  return std::sqrt(variance_of_means / double(counted)) / (mean / double(counted));
}

}  // namespace loom::pathtrace
