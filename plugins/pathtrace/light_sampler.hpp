// Next-event estimation: every emitter of a scene in one alias table,
// selected in proportion to its power (pbrt-v4's PowerLightSampler):
//   emissive triangle  π A lum(Le)        (one-sided: emits on its winding's front)
//   point light        4π I lum(color)
//   spot light         2π (1 - (cos inner + cos outer) / 2) I lum(color)
//   directional light  π r² E lum(color)  (r: the scene's bounding radius)
//   environment map    4π · π r² · mean luminance
// Area samples are uniform on the chosen triangle; their solid-angle density
// is p_select · d² / (A |cos θ_light|) (course report, eqs. 57–61).
#pragma once

#include <optional>
#include <vector>

#include "alias_table.hpp"
#include "embree_scene.hpp"
#include "environment_light.hpp"
#include "loom/scene.hpp"

namespace loom::pathtrace {

struct LightSample {
  Vec3f wi;         // unit, from the shaded point towards the light
  float distance;   // to the light's point; infinity for distant lights
  Vec3f point;      // the light's point (finite lights)
  Vec3f radiance;   // arriving along -wi (for delta lights: intensity / d²)
  float pdf;        // solid angle, selection included; for delta lights the selection alone
  bool delta;
  // Whether a shadow ray decides visibility: false for a Light with
  // casts_shadow off (its light passes through everything). Emissive
  // triangles and the environment always cast shadows.
  bool shadowed;
};

class LightSampler {
 public:
  // `emission[i]` is the emitted radiance of EmbreeScene object i; the
  // environment is sampled only when it has a map (a uniform color is left to
  // BSDF sampling).
  LightSampler(const Scene& scene, const EmbreeScene& traced, const std::vector<Vec3f>& emission,
               const EnvironmentLight& environment);

  bool empty() const { return table_.empty(); }
  bool samples_environment() const { return environment_entry_ >= 0 && !table_.empty(); }
  std::size_t emissive_triangles() const { return triangle_count_; }

  std::optional<LightSample> sample(const Vec3f& p, float uc, const Vec2f& u, float u_env) const;
  // Solid-angle density of sample() choosing the point `hit` seen from `from`.
  float triangle_pdf(const SurfaceHit& hit, const Vec3f& from) const;
  float environment_pdf(const Vec3f& direction) const;

 private:
  struct Entry {
    enum class Kind { triangle, light, environment } kind;
    int object = -1, prim = -1, light = -1;
    float area = 0;
  };
  const EmbreeScene& traced_;
  const EnvironmentLight& environment_;
  // Lights in single precision, as sample() uses them.
  struct PointLike {
    Light::Kind kind;
    Vec3f position, direction, radiance;  // direction unit (zero if none); radiance = color intensity
    float cos_inner, cos_outer;
    bool casts_shadow;
  };
  std::vector<PointLike> lights_;
  std::vector<Vec3f> emission_;
  std::vector<Entry> entries_;
  std::vector<int> first_entry_;  // per traced object: its first triangle entry, or -1
  int environment_entry_ = -1;
  std::size_t triangle_count_ = 0;
  AliasTable table_;
};

}  // namespace loom::pathtrace
