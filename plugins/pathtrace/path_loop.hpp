// One path of integrator.hpp's estimator, as named steps: trace_path takes
// them one path at a time, and the benchmark's lane loop
// (bench/pathtrace/lane_paths.hpp, an experiment of issue 39) 16 paths at a
// time. The steps are defined here, inline, so that both loops compile them
// into their own bodies and draw the same numbers in the same order: one
// rule in one place, and the same bits from either loop.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "bsdf.hpp"
#include "camera_rays.hpp"
#include "embree_scene.hpp"
#include "environment_light.hpp"
#include "integrator.hpp"
#include "light_sampler.hpp"
#include "normal_mapping.hpp"
#include "owen_sobol.hpp"
#include "texture.hpp"

namespace loom::pathtrace {

struct ObjectShading {
  SurfaceMaterial material;
  const Image* base_color_map = nullptr;
  const Image* normal_map = nullptr;  // set only when the traced object keeps UV tangents
  bool reflective_only = true;        // no transmission: directions stay on wo's side of ng
  Vec3f emission = Vec3f::Zero();
  bool emissive = false;
  bool lambert = false;  // diffuse: NEE and sampling in closed form, no local frame
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

// What every path of a render reads of the scene: the materials per traced
// object, the environment, the light sampler.
struct PathScene {
  const EmbreeScene& traced;
  std::vector<ObjectShading> shading;
  EnvironmentLight environment;
  LightSampler lights;
  bool emitters_hittable;  // see PathContext
  PathScene(const Scene& scene, const EmbreeScene& traced, EnvironmentLight::Sampling environment_sampling);
  PathScene(const PathScene&) = delete;  // `lights` refers to `environment`
  PathScene& operator=(const PathScene&) = delete;
  PathContext context(const RenderSettings& settings) const {
    return {traced, shading, lights, environment, settings, emitters_hittable};
  }
};

struct PathResult {
  Vec3f L = Vec3f::Zero();
  Vec3f albedo = Vec3f::Zero(), normal = Vec3f::Zero();
  float depth = 0;
  int rays = 0, shadow_rays = 0;  // closest-hit rays, shadow rays
};

// Where a path is between bounces: its throughput, the next ray's direction,
// and what the emitter that ray may hit needs for its MIS weight.
struct PathVertex {
  Vec3f beta = Vec3f::Ones();
  Vec3f dir;
  float prev_pdf = 0;
  bool prev_delta = true;  // the camera ray: emitters count fully
  Vec3f prev_point;
};

// The light sampling strategy (RenderSettings::strategy) of every bounce.
struct Strategies {
  bool nee, mis;
};
Strategies strategies(const PathContext& c);

// A shadow ray of next-event estimation not traced yet, and the light it
// adds when nothing blocks it.
struct PendingShadow {
  EmbreeScene::Segment ray;
  Vec3f L;
  bool pending = false;
};

// The steps of one path, in the order it takes them.

// Sample `sample` of pixel `index` of a width × height image: its sampler,
// and the camera ray through its jittered point.
PixelSampler start_sample(const PathContext& c, const CameraRays& cam, int width, int height, std::size_t index,
                          int sample, Vec3f& origin, Vec3f& dir);

// Light from the environment along a ray that left the scene, MIS-weighted
// against light sampling's environment pdf.
void add_environment(const PathContext& c, const PathVertex& v, Strategies use, int depth, PathResult& r);

// The surface the path arrived at: the normal map applied to hit.ns, the
// first hit's AOVs, the emission seen (MIS-weighted). Returns the base
// colour there; `wo_side` is set to what cuts directions through the
// geometric surface (0: nothing is cut).
Vec3f arrive(const PathContext& c, Strategies use, const PathVertex& v, int depth, SurfaceHit& hit, PathResult& r,
             float& wo_side);

// Next-event estimation's light sample at the hit (its numbers drawn first).
std::optional<LightSample> sample_light(const PathContext& c, const SurfaceHit& hit, PixelSampler& sampler);
// A light sample's contribution L: added now, or left in `shadow` for the
// caller to trace when a shadow ray decides.
void add_light(const PathContext& c, const SurfaceHit& hit, const LightSample& ls, const Vec3f& L, PathResult& r,
               PendingShadow& shadow);

// The bounce at the hit, for any material: direct light, then the
// BSDF-sampled direction the path continues in (v). False when it ends here.
bool scatter(const PathContext& c, const SurfaceHit& hit, float wo_side, const ObjectShading& sh, const Vec3f& base,
             Strategies use, PixelSampler& sampler, PathVertex& v, PathResult& r);

// After a bounce at `hit` at `depth`: whether the path goes on (its
// throughput, the last bounce, Russian roulette), and if so the next ray's
// origin.
bool next_ray(const PathContext& c, const SurfaceHit& hit, int depth, PixelSampler& sampler, PathVertex& v,
              Vec3f& origin);

// One path from the camera ray (origin, dir), one ray at a time.
PathResult trace_path(const PathContext& c, Vec3f origin, Vec3f dir, PixelSampler& sampler);

// The steps' definitions, inline: both loops take them at every bounce.

// The far end of a ray that has none (camera and bounce rays, distant lights).
constexpr float kInf = std::numeric_limits<float>::infinity();

namespace path_detail {

// A scattered direction: weight = f cos θ / pdf.
struct Scattered {
  Vec3f weight, dir;
  float pdf;
  bool delta;
};

// Each BSDF form gives next-event estimation a Term for a light's direction:
// f cos θ = factor · scale (kept apart so the product rounds the same way for
// both forms), whether it is nonzero, and what its pdf() needs.

// Lambert, two-sided, in closed form with no local frame: f cos θi = base cos θi / π
// on wo's side of the shading normal, pdf = cos θi / π (cosine sampling), weight = base.
struct LambertBsdf {
  Vec3f n;  // the shading normal turned to wo's side
  Vec3f base;
  struct Term {
    Vec3f factor;
    float scale;
    bool nonzero;
  };
  bool nonspecular() const { return true; }
  Term direct(const Vec3f& wi) const {
    const float cos_i = n.dot(wi);
    return {base, cos_i * kInvPi, cos_i > 0};
  }
  float pdf(const Term& t) const { return t.scale; }
  std::optional<Scattered> sample(PixelSampler& sampler) const {
    const Vec3f wi = sample_cosine_hemisphere(sampler.uniform2(Decision::direction));
    if (!(wi.z() > 0)) return std::nullopt;
    return Scattered{base, unit(Frame(n).to_world(wi)), wi.z() * kInvPi, false};
  }
};

// Every other model through bsdf.hpp, in the shading frame.
struct FramedBsdf {
  SurfaceMaterial m;
  Frame frame;
  Vec3f wo;
  struct Term {
    Vec3f factor;
    float scale;
    bool nonzero;
    Vec3f wi_local;
  };
  bool nonspecular() const { return !m.purely_specular(); }
  Term direct(const Vec3f& wi) const {
    const Vec3f local = frame.to_local(wi);
    const Vec3f f = bsdf_eval(m, wo, local);
    return {f, 1.f, (f.array() > 0).any(), local};
  }
  float pdf(const Term& t) const { return bsdf_pdf(m, wo, t.wi_local); }
  std::optional<Scattered> sample(PixelSampler& sampler) const {
    const float uc = sampler.uniform(Decision::lobe);
    const auto bs = bsdf_sample(m, wo, uc, sampler.uniform2(Decision::direction));
    if (!bs || !(bs->weight.array() > 0).any()) return std::nullopt;
    return Scattered{bs->weight, unit(frame.to_world(bs->wi)), bs->pdf, bs->delta};
  }
};

// Next-event estimation (pbrt-v4's SampleLd): one light sample, its shadow
// ray, f Le w_light / p_light with w_light the power heuristic against the
// BSDF's pdf (1 for delta lights or without MIS). `wo_side` cuts directions
// through the geometric surface (normal maps, reflection only). β enters the
// product first, as the path loop always multiplied. A shadowed light's
// contribution is left in `shadow` for the caller to trace.
template <class Bsdf>
void sample_direct(const PathContext& c, const SurfaceHit& hit, float wo_side, const Bsdf& bsdf, const Vec3f& beta,
                   bool use_mis, PixelSampler& sampler, PathResult& r, PendingShadow& shadow) {
  const auto ls = sample_light(c, hit, sampler);
  if (!ls) return;
  const auto t = bsdf.direct(ls->wi);
  if (!t.nonzero || !(wo_side * ls->wi.dot(hit.ng) >= 0)) return;
  const float w = ls->delta || !use_mis ? 1.f : power_heuristic(ls->pdf, bsdf.pdf(t));
  add_light(c, hit, *ls, beta.cwiseProduct(t.factor).cwiseProduct(ls->radiance) * (t.scale * w / ls->pdf), r, shadow);
}

// One bounce at a hit: direct light, then the BSDF-sampled direction the path
// continues in. False when the path ends here. The shadow ray is traced
// after the direction is sampled, which does not depend on it: issued
// first, that chain of dependent arithmetic (warp, frame, normalization)
// runs while Embree's occlusion kernel starts, instead of after it returns.
template <class Bsdf>
bool scatter_by(const PathContext& c, const SurfaceHit& hit, float wo_side, const Bsdf& bsdf, Strategies use,
                PixelSampler& sampler, PathVertex& v, PathResult& r) {
  PendingShadow shadow;
  if (use.nee && bsdf.nonspecular()) sample_direct(c, hit, wo_side, bsdf, v.beta, use.mis, sampler, r, shadow);
  const auto s = bsdf.sample(sampler);
  if (shadow.pending && !c.traced.occluded(shadow.ray.origin, shadow.ray.direction, shadow.ray.tmax)) r.L += shadow.L;
  if (!s) return false;
  v.beta = v.beta.cwiseProduct(s->weight);
  v.prev_pdf = s->pdf;
  v.prev_delta = s->delta;
  v.dir = s->dir;
  return !(wo_side * v.dir.dot(hit.ng) < 0);
}

}  // namespace path_detail

inline Strategies strategies(const PathContext& c) {
  return {c.settings.strategy != Strategy::bsdf && !c.lights.empty(), c.settings.strategy == Strategy::mis};
}

inline PixelSampler start_sample(const PathContext& c, const CameraRays& cam, int width, int height, std::size_t index,
                                 int sample, Vec3f& origin, Vec3f& dir) {
  PixelSampler sampler(c.settings.sampler, c.settings.seed, index, std::uint64_t(sample));
  const Vec2f j = sampler.camera_jitter();
  cam.ray(2 * (float(index % std::size_t(width)) + j.x()) / width - 1,
          1 - 2 * (float(index / std::size_t(width)) + j.y()) / height, &origin, &dir);
  return sampler;
}

inline std::optional<LightSample> sample_light(const PathContext& c, const SurfaceHit& hit, PixelSampler& sampler) {
  const Vec2f u = c.lights.reads_point() ? sampler.uniform2(Decision::light) : Vec2f::Zero();
  // The environment map's pixel.
  const float ue = c.lights.samples_environment() ? sampler.uniform(Decision::environment_pixel) : 0.f;
  return c.lights.sample(hit.p, u, ue);
}

inline void add_light(const PathContext& c, const SurfaceHit& hit, const LightSample& ls, const Vec3f& L, PathResult& r,
                      PendingShadow& shadow) {
  if (ls.shadowed) {
    ++r.shadow_rays;
    shadow.ray = std::isinf(ls.distance) ? EmbreeScene::Segment{c.traced.offset(hit, ls.wi), ls.wi, kInf}
                                         : c.traced.shadow_segment(hit, ls.point);
    shadow.L = L;
    shadow.pending = shadow.ray.tmax > 0;  // else nothing lies between: unblocked
    if (shadow.pending) return;
  }
  r.L += L;
}

// Light from the environment along a ray that left the scene, MIS-weighted
// against light sampling's environment pdf.
inline void add_environment(const PathContext& c, const PathVertex& v, Strategies use, int depth, PathResult& r) {
  if (c.environment.black()) return;
  float w = 1;
  if (!v.prev_delta && use.nee && c.lights.samples_environment())
    w = use.mis ? power_heuristic(v.prev_pdf, c.lights.environment_pdf(v.dir)) : 0.f;
  r.L += v.beta.cwiseProduct(c.environment.radiance(v.dir)) * w;
  if (depth == 0) r.albedo = c.environment.radiance(v.dir);
}

inline Vec3f arrive(const PathContext& c, Strategies use, const PathVertex& v, int depth, SurfaceHit& hit,
                    PathResult& r, float& wo_side) {
  const ObjectShading& sh = c.shading[std::size_t(hit.object)];
  // With a normal map, a direction on the other side of the geometric
  // surface than wo is cut (reflection only: it would pass through).
  wo_side = 0;
  if (sh.normal_map) {
    hit.ns = mapped_normal(hit.ns, hit.dpdu, hit.dpdv, texel_bilinear(*sh.normal_map, hit.uv));
    hit.ns = bend_above_horizon(hit.ns, hit.ng, -v.dir);
    if (sh.reflective_only) wo_side = -v.dir.dot(hit.ng);
  }
  Vec3f base = sh.material.base.cwiseProduct(hit.color);
  if (sh.base_color_map) base = base.cwiseProduct(texel_color(*sh.base_color_map, hit.uv));
  if (depth == 0) {
    r.albedo = base;
    r.normal = hit.ns;
    r.depth = hit.t;
  }
  // Emission (one-sided, on the winding's front).
  if (sh.emissive && hit.ng.dot(v.dir) < 0) {
    float w = 1;
    if (!v.prev_delta && use.nee && !c.traced.objects()[std::size_t(hit.object)].spheres)
      w = use.mis ? power_heuristic(v.prev_pdf, c.lights.triangle_pdf(hit, v.prev_point)) : 0.f;
    r.L += v.beta.cwiseProduct(sh.emission) * w;
  }
  return base;
}

inline bool scatter(const PathContext& c, const SurfaceHit& hit, float wo_side, const ObjectShading& sh,
                    const Vec3f& base, Strategies use, PixelSampler& sampler, PathVertex& v, PathResult& r) {
  if (sh.lambert)
    return path_detail::scatter_by(c, hit, wo_side,
                                   path_detail::LambertBsdf{hit.ns.dot(v.dir) > 0 ? Vec3f(-hit.ns) : hit.ns, base}, use,
                                   sampler, v, r);
  SurfaceMaterial m = sh.material;
  m.base = base;
  const Frame frame(hit.ns);
  return path_detail::scatter_by(c, hit, wo_side, path_detail::FramedBsdf{m, frame, frame.to_local(-v.dir)}, use,
                                 sampler, v, r);
}

inline bool next_ray(const PathContext& c, const SurfaceHit& hit, int depth, PixelSampler& sampler, PathVertex& v,
                     Vec3f& origin) {
  v.prev_point = hit.p;
  // A path that can gather nothing more ends here: its throughput is zero
  // (e.g. red after green), or the next hit would be past the last bounce
  // and could only add emission the scene does not have.
  if (!(v.beta.maxCoeff() > 0)) return false;
  if (depth + 1 >= c.settings.max_depth && !c.emitters_hittable) return false;
  origin = c.traced.offset(hit, v.dir);
  if (c.settings.russian_roulette && depth + 1 >= c.settings.rr_min_depth) {
    const float survive = std::min(0.95f, v.beta.maxCoeff());
    if (!(sampler.uniform(Decision::roulette) < survive)) return false;
    v.beta /= survive;
  }
  return v.beta.allFinite();
}

}  // namespace loom::pathtrace
