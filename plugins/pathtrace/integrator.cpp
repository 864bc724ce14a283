#include "integrator.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "bsdf.hpp"
#include "light_sampler.hpp"
#include "normal_mapping.hpp"
#include "texture.hpp"

namespace loom::pathtrace {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct ObjectShading {
  SurfaceMaterial material;
  const Image* base_color_map = nullptr;
  const Image* normal_map = nullptr;  // set only when the traced object keeps UV tangents
  bool reflective_only = true;        // no transmission: directions stay on wo's side of ng
  Vec3f emission = Vec3f::Zero();
  bool emissive = false;
  bool lambert = false;  // diffuse: NEE and sampling in closed form, no local frame
};

struct CameraRays {
  Vec3f eye, forward, right, up;
  float tan_half = 1, ortho_half = 1, aspect = 1;
  bool ortho = false;
  CameraRays(const Camera& c, int width, int height) {
    eye = c.eye.cast<float>();
    forward = (c.target - c.eye).cast<float>();
    if (!(forward.squaredNorm() > 0)) forward = Vec3f(0, 0, -1);
    forward.normalize();
    right = forward.cross(c.up.cast<float>());
    if (!(right.squaredNorm() > 1e-12f)) right = forward.cross(std::fabs(forward.y()) < 0.9f ? Vec3f(0, 1, 0) : Vec3f(1, 0, 0));
    right.normalize();
    up = right.cross(forward);
    tan_half = std::tan(float(c.fov_y) / 2);
    ortho_half = float(c.ortho_height) / 2;
    aspect = float(width) / float(height);
    ortho = c.projection == Camera::Projection::orthographic;
  }
  // (sx, sy) in [-1, 1]², y up.
  void ray(float sx, float sy, Vec3f* origin, Vec3f* dir) const {
    if (ortho) {
      *origin = eye + ortho_half * (sx * aspect * right + sy * up);
      *dir = forward;
    } else {
      *origin = eye;
      *dir = unit(forward + tan_half * (sx * aspect * right + sy * up));
    }
  }
};

struct PathContext {
  const EmbreeScene& traced;
  const std::vector<ObjectShading>& shading;
  const LightSampler& lights;
  const EnvironmentLight& environment;
  const RenderSettings& settings;
  // Whether a BSDF-sampled ray can find light at all (an emissive object or
  // the environment): if not, the ray after the last bounce is not traced.
  bool emitters_hittable;
};

struct PathResult {
  Vec3f L = Vec3f::Zero();
  Vec3f albedo = Vec3f::Zero(), normal = Vec3f::Zero();
  float depth = 0;
  int rays = 0;
};

// The shadow ray of next-event estimation.
bool occluded(const EmbreeScene& traced, const SurfaceHit& hit, const LightSample& ls) {
  return std::isinf(ls.distance) ? traced.occluded(traced.offset(hit, ls.wi), ls.wi, kInf)
                                 : traced.occluded_to(hit, ls.point);
}

PathResult trace_path(const PathContext& c, Vec3f origin, Vec3f dir, Rng& rng) {
  PathResult r;
  const bool use_nee = c.settings.strategy != Strategy::bsdf && !c.lights.empty();
  const bool use_mis = c.settings.strategy == Strategy::mis;
  Vec3f beta = Vec3f::Ones();
  float prev_pdf = 0;
  bool prev_delta = true;  // the camera ray: emitters count fully
  Vec3f prev_point = origin;
  SurfaceHit hit;
  for (int depth = 0;; ++depth) {
    ++r.rays;
    if (!c.traced.intersect(origin, dir, kInf, &hit, depth == 0)) {
      if (!c.environment.black()) {
        float w = 1;
        if (!prev_delta && use_nee && c.lights.samples_environment())
          w = use_mis ? power_heuristic(prev_pdf, c.lights.environment_pdf(dir)) : 0.f;
        r.L += beta.cwiseProduct(c.environment.radiance(dir)) * w;
        if (depth == 0) r.albedo = c.environment.radiance(dir);
      }
      break;
    }
    const ObjectShading& sh = c.shading[hit.object];
    // With a normal map, a direction on the other side of the geometric
    // surface than wo is cut (reflection only: it would pass through).
    float wo_side = 0;
    if (sh.normal_map) {
      hit.ns = mapped_normal(hit.ns, hit.dpdu, hit.dpdv, texel_bilinear(*sh.normal_map, hit.uv));
      hit.ns = bend_above_horizon(hit.ns, hit.ng, -dir);
      if (sh.reflective_only) wo_side = -dir.dot(hit.ng);
    }
    Vec3f base = sh.material.base.cwiseProduct(hit.color);
    if (sh.base_color_map) base = base.cwiseProduct(texel_color(*sh.base_color_map, hit.uv));
    if (depth == 0) {
      r.albedo = base;
      r.normal = hit.ns;
      r.depth = hit.t;
    }
    // Emission (one-sided, on the winding's front).
    if (sh.emissive && hit.ng.dot(dir) < 0) {
      float w = 1;
      if (!prev_delta && use_nee && !c.traced.objects()[hit.object].spheres)
        w = use_mis ? power_heuristic(prev_pdf, c.lights.triangle_pdf(hit, prev_point)) : 0.f;
      r.L += beta.cwiseProduct(sh.emission) * w;
    }
    if (depth >= c.settings.max_depth) break;

    if (sh.lambert) {
      // Lambert, two-sided: f cos = base cos θi / π on wo's side of the
      // shading normal, pdf = cos θi / π (cosine sampling), weight = base.
      const Vec3f n = hit.ns.dot(dir) > 0 ? Vec3f(-hit.ns) : hit.ns;
      if (use_nee) {
        const float uc = rng.uniform();
        const Vec2f u = rng.uniform2();
        const float ue = rng.uniform();
        if (const auto ls = c.lights.sample(hit.p, uc, u, ue)) {
          const float cos_i = n.dot(ls->wi);
          if (cos_i > 0 && wo_side * ls->wi.dot(hit.ng) >= 0) {
            const bool blocked = ls->shadowed && (++r.rays, occluded(c.traced, hit, *ls));
            if (!blocked) {
              const float bsdf_pdf = cos_i * kInvPi;
              const float w = ls->delta || !use_mis ? 1.f : power_heuristic(ls->pdf, bsdf_pdf);
              r.L += beta.cwiseProduct(base).cwiseProduct(ls->radiance) * (bsdf_pdf * w / ls->pdf);
            }
          }
        }
      }
      const Vec3f wi = sample_cosine_hemisphere(rng.uniform2());
      if (!(wi.z() > 0)) break;
      beta = beta.cwiseProduct(base);
      prev_pdf = wi.z() * kInvPi;
      prev_delta = false;
      dir = unit(Frame(n).to_world(wi));
      if (wo_side * dir.dot(hit.ng) < 0) break;
    } else {
      SurfaceMaterial m = sh.material;
      m.base = base;
      const Frame frame(hit.ns);
      const Vec3f wo = frame.to_local(-dir);
      // Next-event estimation.
      if (use_nee && !m.purely_specular()) {
        const float uc = rng.uniform();
        const Vec2f u = rng.uniform2();
        const float ue = rng.uniform();
        if (const auto ls = c.lights.sample(hit.p, uc, u, ue)) {
          const Vec3f wi = frame.to_local(ls->wi);
          const Vec3f f = bsdf_eval(m, wo, wi);
          if ((f.array() > 0).any() && wo_side * ls->wi.dot(hit.ng) >= 0) {
            const bool blocked = ls->shadowed && (++r.rays, occluded(c.traced, hit, *ls));
            if (!blocked) {
              const float w =
                  ls->delta || !use_mis ? 1.f : power_heuristic(ls->pdf, bsdf_pdf(m, wo, wi));
              r.L += beta.cwiseProduct(f).cwiseProduct(ls->radiance) * (w / ls->pdf);
            }
          }
        }
      }
      // BSDF sampling.
      const float uc = rng.uniform();
      const auto bs = bsdf_sample(m, wo, uc, rng.uniform2());
      if (!bs || !(bs->weight.array() > 0).any()) break;
      beta = beta.cwiseProduct(bs->weight);
      prev_pdf = bs->pdf;
      prev_delta = bs->delta;
      dir = unit(frame.to_world(bs->wi));
      if (wo_side * dir.dot(hit.ng) < 0) break;
    }
    prev_point = hit.p;
    // A path that can gather nothing more ends here: its throughput is zero
    // (e.g. red after green), or the next hit would be past the last bounce
    // and could only add emission the scene does not have.
    if (!(beta.maxCoeff() > 0)) break;
    if (depth + 1 >= c.settings.max_depth && !c.emitters_hittable) break;
    origin = c.traced.offset(hit, dir);
    if (c.settings.russian_roulette && depth + 1 >= c.settings.rr_min_depth) {
      const float survive = std::min(0.95f, beta.maxCoeff());
      if (!(rng.uniform() < survive)) break;
      beta /= survive;
    }
    if (!beta.allFinite()) break;
  }
  return r;
}

struct PixelAccumulator {
  double L[3] = {0, 0, 0};
  double albedo[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
  double depth = 0, lum = 0, lum2 = 0;
  int n = 0;
  bool done = false;
};

}  // namespace

RenderResult render(const Scene& scene, const Camera& camera, const EmbreeScene& traced,
                    const RenderSettings& s, const std::function<void(double)>& between_batches) {
  const int W = s.width, H = s.height;
  std::vector<ObjectShading> shading(traced.objects().size());
  std::vector<Vec3f> emission(traced.objects().size());
  bool emitters_hittable = false;
  for (std::size_t i = 0; i < shading.size(); ++i) {
    const Material& mat = scene.objects[traced.objects()[i].scene_index].material;
    ObjectShading& sh = shading[i];
    sh.material.model = mat.model;
    sh.material.base = mat.base_color.cast<float>();
    const float rough = float(std::clamp(mat.roughness, 0.0, 1.0));
    sh.material.ggx.alpha = rough * rough;
    sh.material.ior = float(std::max(mat.ior, 1.0));
    if (mat.base_color_map && !mat.base_color_map->empty()) sh.base_color_map = mat.base_color_map.get();
    if (mat.normal_map && !mat.normal_map->empty() && !traced.objects()[i].dPdu.empty())
      sh.normal_map = mat.normal_map.get();
    sh.reflective_only = mat.model != Material::Model::dielectric;
    sh.emission = mat.emission.cast<float>();
    sh.emissive = (sh.emission.array() > 0).any();
    sh.lambert = mat.model == Material::Model::diffuse;
    emission[i] = sh.emission;
    emitters_hittable |= sh.emissive;
  }
  const EnvironmentLight environment(scene.environment, s.environment_sampling);
  const LightSampler lights(scene, traced, emission, environment);
  const PathContext context{traced, shading, lights, environment, s,
                            emitters_hittable || !environment.black()};
  const CameraRays cam(camera, W, H);

  std::vector<PixelAccumulator> acc(std::size_t(W) * H);
  constexpr int kTile = 16;
  const int tiles_x = (W + kTile - 1) / kTile, tiles_y = (H + kTile - 1) / kTile;
  const int tiles = tiles_x * tiles_y;
  std::atomic<std::uint64_t> rays{0}, nonfinite{0};
  std::uint64_t paths = 0;
  const bool adaptive = s.adaptive_threshold > 0;
  const double total = double(W) * H * s.spp;
  int taken = 0;  // samples per active pixel so far
  while (taken < s.spp) {
    const int pass = !adaptive ? s.spp - taken
                               : (taken == 0 ? std::min(s.spp, std::max(1, s.adaptive_min_spp))
                                             : std::min(s.spp - taken, std::max(4, taken / 4)));
    constexpr int kBatch = 32;  // tiles between progress reports and cancellation checks
    for (int first = 0; first < tiles; first += kBatch) {
      const int last = std::min(tiles, first + kBatch);
      tbb::parallel_for(tbb::blocked_range<int>(first, last, 1), [&](const tbb::blocked_range<int>& range) {
        std::uint64_t local_rays = 0, local_bad = 0;
        for (int tile = range.begin(); tile != range.end(); ++tile) {
          const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
          for (int y = y0; y < std::min(H, y0 + kTile); ++y)
            for (int x = x0; x < std::min(W, x0 + kTile); ++x) {
              const std::size_t index = std::size_t(y) * W + x;
              PixelAccumulator& a = acc[index];
              if (a.done) continue;
              for (int k = 0; k < pass; ++k) {
                Rng rng(s.seed, index, std::uint64_t(a.n));
                const Vec2f j = rng.uniform2();
                Vec3f origin, dir;
                cam.ray(2 * (x + j.x()) / W - 1, 1 - 2 * (y + j.y()) / H, &origin, &dir);
                const PathResult p = trace_path(context, origin, dir, rng);
                local_rays += std::uint64_t(p.rays);
                ++a.n;
                if (!p.L.allFinite()) {
                  ++local_bad;  // counted as a black sample: the mean stays finite
                  continue;
                }
                const float lum = luminance(p.L);
                for (int i = 0; i < 3; ++i) {
                  a.L[i] += p.L[i];
                  a.albedo[i] += p.albedo[i];
                  a.normal[i] += p.normal[i];
                }
                a.depth += p.depth;
                a.lum += lum;
                a.lum2 += double(lum) * lum;
              }
            }
        }
        rays += local_rays;
        nonfinite += local_bad;
      });
      if (between_batches) {
        double done = 0;
        for (const auto& a : acc) done += a.n;
        between_batches(std::min(1.0, done / total));
      }
    }
    taken += pass;
    if (adaptive && taken < s.spp) {
      for (auto& a : acc) {
        if (a.done || a.n < 2) continue;
        const double mean = a.lum / a.n;
        const double var = std::max(0.0, (a.lum2 - a.lum * mean) / (a.n - 1));
        // Relative standard error of the mean, with a floor for black pixels.
        a.done = std::sqrt(var / a.n) < s.adaptive_threshold * std::max(mean, 1e-3);
      }
    }
  }
  RenderResult out;
  out.image.create(H, W, CV_32FC3);
  out.albedo.create(H, W, CV_32FC3);
  out.normal.create(H, W, CV_32FC3);
  out.depth.create(H, W, CV_32FC1);
  out.samples.create(H, W, CV_32FC1);
  double sum_n = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const PixelAccumulator& a = acc[std::size_t(y) * W + x];
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
  out.rays = rays;
  out.nonfinite = nonfinite;
  out.emissive_triangles = lights.emissive_triangles();
  out.environment_sampled = lights.samples_environment();
  return out;
}

}  // namespace loom::pathtrace
