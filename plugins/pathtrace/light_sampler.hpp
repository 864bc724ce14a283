// Next-event estimation: every emitter of a scene in one table, selected in
// proportion to its power (pbrt-v4's PowerLightSampler) by inverting the
// cumulative distribution with u.x, whose rest is then reused as the first
// coordinate of the point on the chosen emitter (cdf_table.hpp), so one 2D
// point stratifies the surfaces of all emitters together:
//   emissive triangle  π A lum(Le)        (one-sided: emits on its winding's front)
//   point light        4π I lum(color)
//   spot light         2π (1 - (cos inner + cos outer) / 2) I lum(color)
//   directional light  π r² E lum(color)  (r: the scene's bounding radius)
//   environment map    4π · π r² · mean luminance
// Area samples are uniform on the chosen triangle; their solid-angle density
// is p_select · d² / (A |cos θ_light|) (course report, eqs. 57–61).
#pragma once

#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "cdf_table.hpp"
#include "embree_scene.hpp"
#include "environment_light.hpp"
#include "loom/scene.hpp"

namespace loom::pathtrace {

struct LightSample {
  Vec3f wi;        // unit, from the shaded point towards the light
  float distance;  // to the light's point; infinity for distant lights
  Vec3f point;     // the light's point (finite lights)
  Vec3f radiance;  // arriving along -wi (for delta lights: intensity / d²)
  float pdf;       // solid angle, selection included; for delta lights the selection alone
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
  // Whether sample() reads its point u: not for a lone point, spot or
  // directional light (nothing to select, nothing to place).
  bool reads_point() const { return !(entries_.size() == 1 && entries_[0].kind == Entry::Kind::light); }

  // Defined inline below, so that the path loop (integrator.cpp) may inline
  // it: it runs at every bounce. (GCC 12 at -O3 keeps it a call there;
  // forced inline, PathTrace's ray rate did not change beyond the noise:
  // eight alternating `bench_pathtrace --quick rays` pairs, 2026-11-30.)
  // u.x selects the emitter and, rescaled, u.x and u.y place the point on it.
  std::optional<LightSample> sample(const Vec3f& p, const Vec2f& u, float u_env) const;
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
  std::optional<LightSample> sample_environment(float select, float u_env, const Vec2f& u) const;
  std::vector<PointLike> lights_;
  std::vector<Vec3f> emission_;
  std::vector<Entry> entries_;
  std::vector<int> first_entry_;  // per traced object: its first triangle entry, or -1
  int environment_entry_ = -1;
  std::size_t triangle_count_ = 0;
  CdfTable table_;
};

inline float spot_falloff(const Vec3f& direction, float cos_inner, float cos_outer, const Vec3f& from_light) {
  const float c = from_light.dot(direction);
  const float ci = cos_inner, co = cos_outer;
  if (c >= ci) return 1;
  if (c <= co || ci <= co) return 0;
  const float t = (c - co) / (ci - co);
  return t * t * (3 - 2 * t);
}

inline std::optional<LightSample> LightSampler::sample(const Vec3f& p, const Vec2f& u_select, float u_env) const {
  if (table_.empty()) return std::nullopt;
  const CdfTable::Choice choice = table_.sample(u_select.x());
  const std::uint32_t index = choice.index;
  const Vec2f u(choice.remainder, u_select.y());
  const float select = table_.pmf(index);
  if (!(select > 0)) return std::nullopt;
  const Entry& e = entries_[index];
  constexpr float inf = std::numeric_limits<float>::infinity();
  switch (e.kind) {
    case Entry::Kind::triangle: {
      const TracedObject& o = traced_.objects()[e.object];
      const auto& t = o.F[e.prim];
      const Vec2f b = sample_uniform_triangle(u);
      const Vec3f q = (1 - b.x() - b.y()) * o.P[t[0]] + b.x() * o.P[t[1]] + b.y() * o.P[t[2]];
      const Vec3f& n = o.face_normal[e.prim];  // unit, by the winding
      Vec3f d = q - p;
      const float dist2 = d.squaredNorm();
      if (!(dist2 > 0)) return std::nullopt;
      const float dist = std::sqrt(dist2);
      d *= 1 / dist;
      const float cos_light = -n.dot(d);
      if (!(cos_light > 0)) return std::nullopt;  // the back of a one-sided emitter
      const float pdf = select * dist2 / (e.area * cos_light);
      if (!std::isfinite(pdf)) return std::nullopt;
      return LightSample{d, dist, q, emission_[e.object], pdf, false, true};
    }
    case Entry::Kind::light: {
      const PointLike& l = lights_[e.light];
      if (l.kind == Light::Kind::directional) {
        if (l.direction.x() == 0 && l.direction.y() == 0 && l.direction.z() == 0) return std::nullopt;
        return LightSample{-l.direction, inf, Vec3f::Zero(), l.radiance, select, true, l.casts_shadow};
      }
      Vec3f d = l.position - p;
      const float dist2 = d.squaredNorm();
      if (!(dist2 > 0)) return std::nullopt;
      const float inv_dist = inv_sqrt(dist2);
      d *= inv_dist;
      float k = inv_dist * inv_dist;
      if (l.kind == Light::Kind::spot) k *= spot_falloff(l.direction, l.cos_inner, l.cos_outer, -d);
      if (!(k > 0) || !std::isfinite(k)) return std::nullopt;
      return LightSample{d, dist2 * inv_dist, l.position, l.radiance * k, select, true, l.casts_shadow};
    }
    case Entry::Kind::environment:
      return sample_environment(select, u_env, u);
  }
  return std::nullopt;
}

}  // namespace loom::pathtrace
