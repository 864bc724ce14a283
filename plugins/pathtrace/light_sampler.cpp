#include "light_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace loom::pathtrace {

namespace {

template <class L>
float spot_falloff(const L& l, const Vec3f& from_light) {
  const float c = from_light.dot(l.direction);
  const float ci = l.cos_inner, co = l.cos_outer;
  if (c >= ci) return 1;
  if (c <= co || ci <= co) return 0;
  const float t = (c - co) / (ci - co);
  return t * t * (3 - 2 * t);
}

}  // namespace

LightSampler::LightSampler(const Scene& scene, const EmbreeScene& traced,
                           const std::vector<Vec3f>& emission, const EnvironmentLight& environment)
    : traced_(traced), environment_(environment), emission_(emission) {
  for (const Light& l : scene.lights) {
    const Vec3f d = l.direction.cast<float>();
    lights_.push_back({l.kind, l.position.cast<float>(),
                       d.squaredNorm() > 0 ? Vec3f(d.normalized()) : Vec3f(Vec3f::Zero()),
                       l.color.cast<float>() * float(l.intensity), std::cos(float(l.spot_inner)),
                       std::cos(float(l.spot_outer)), l.casts_shadow});
  }
  std::vector<double> power;
  const auto& objects = traced.objects();
  first_entry_.assign(objects.size(), -1);
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const TracedObject& o = objects[i];
    const float lum = luminance(emission[i]);
    if (o.spheres || !(lum > 0)) continue;
    first_entry_[i] = int(entries_.size());
    for (std::size_t f = 0; f < o.F.size(); ++f) {
      const auto& t = o.F[f];
      const float area = 0.5f * (o.P[t[1]] - o.P[t[0]]).cross(o.P[t[2]] - o.P[t[0]]).norm();
      // Zero-area triangles stay in the table with weight 0: never chosen, pdf 0.
      const bool ok = std::isfinite(area) && area > 0;
      entries_.push_back({Entry::Kind::triangle, int(i), int(f), -1, ok ? area : 0.f});
      power.push_back(ok ? kPi * area * lum : 0.0);
      triangle_count_ += ok;
    }
  }
  const double radius = 0.5 * traced.extent();
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    const double lum = std::max(0.f, luminance(l.color.cast<float>())) * l.intensity;
    double p = 0;
    switch (l.kind) {
      case Light::Kind::point: p = 4 * kPi * lum; break;
      case Light::Kind::spot:
        p = 2 * kPi * (1 - 0.5 * (std::cos(l.spot_inner) + std::cos(l.spot_outer))) * lum;
        break;
      case Light::Kind::directional: p = kPi * radius * radius * lum; break;
    }
    entries_.push_back({Entry::Kind::light, -1, -1, int(i), 0});
    power.push_back(p);
  }
  if (!environment.black() && environment.has_map()) {
    environment_entry_ = int(entries_.size());
    entries_.push_back({Entry::Kind::environment, -1, -1, -1, 0});
    power.push_back(4 * kPi * kPi * radius * radius * environment.mean_luminance());
  }
  table_ = AliasTable(power);
}

std::optional<LightSample> LightSampler::sample(const Vec3f& p, float uc, const Vec2f& u,
                                                float u_env) const {
  if (table_.empty()) return std::nullopt;
  const std::uint32_t index = table_.sample(uc);
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
      const Vec3f n = (o.P[t[1]] - o.P[t[0]]).cross(o.P[t[2]] - o.P[t[0]]).normalized();
      Vec3f d = q - p;
      const float dist2 = d.squaredNorm();
      if (!(dist2 > 0)) return std::nullopt;
      const float dist = std::sqrt(dist2);
      d /= dist;
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
      const float dist = std::sqrt(dist2);
      d /= dist;
      float k = 1 / dist2;
      if (l.kind == Light::Kind::spot) k *= spot_falloff(l, -d);
      if (!(k > 0)) return std::nullopt;
      return LightSample{d, dist, l.position, l.radiance * k, select, true, l.casts_shadow};
    }
    case Entry::Kind::environment: {
      const auto s = environment_.sample(u_env, u);
      if (!(s.pdf > 0)) return std::nullopt;
      return LightSample{s.direction, inf, Vec3f::Zero(), environment_.radiance(s.direction), select * s.pdf, false, true};
    }
  }
  return std::nullopt;
}

float LightSampler::triangle_pdf(const SurfaceHit& hit, const Vec3f& from) const {
  if (hit.object < 0 || first_entry_[hit.object] < 0) return 0;
  const std::size_t index = std::size_t(first_entry_[hit.object] + hit.prim);
  const Entry& e = entries_[index];
  if (!(e.area > 0)) return 0;
  const Vec3f d = hit.p - from;
  const float dist2 = d.squaredNorm();
  const float cos_light = std::fabs(hit.ng.dot(d)) / std::sqrt(dist2);
  if (!(cos_light > 0)) return 0;
  return table_.pmf(index) * dist2 / (e.area * cos_light);
}

float LightSampler::environment_pdf(const Vec3f& direction) const {
  if (environment_entry_ < 0 || table_.empty()) return 0;
  return table_.pmf(std::size_t(environment_entry_)) * environment_.pdf(direction);
}

}  // namespace loom::pathtrace
