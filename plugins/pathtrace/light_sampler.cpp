#include "light_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace loom::pathtrace {

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
  table_ = CdfTable(power);
}

std::optional<LightSample> LightSampler::sample_environment(float select, float u_env,
                                                            const Vec2f& u) const {
  const auto s = environment_.sample(u_env, u);
  if (!(s.pdf > 0)) return std::nullopt;
  constexpr float inf = std::numeric_limits<float>::infinity();
  return LightSample{s.direction, inf, Vec3f::Zero(), environment_.radiance(s.direction), select * s.pdf, false, true};
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
