// One path of integrator.hpp's estimator, as steps that both path loops
// take: the scalar loop (trace_path, one path at a time) and the lane loop
// (lane_paths.hpp, 16 paths at a time, Lambertian bounces in SIMD). Each
// step is one rule in one place, so the two loops draw the same numbers in
// the same order and give the same image, bit for bit.
#pragma once

#include <optional>
#include <vector>

#include "bsdf.hpp"
#include "embree_scene.hpp"
#include "environment_light.hpp"
#include "integrator.hpp"
#include "light_sampler.hpp"
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

// The scene's materials as the path loop reads them, per traced object.
std::vector<ObjectShading> object_shading(const Scene& scene, const EmbreeScene& traced);

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

// The steps of one bounce, in the order a path takes them.

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

}  // namespace loom::pathtrace
