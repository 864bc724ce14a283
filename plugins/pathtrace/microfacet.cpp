#include "microfacet.hpp"

#include <algorithm>

namespace loom::pathtrace {

float Ggx::D(const Vec3f& h) const {
  if (h.z() <= 0) return 0;
  const float cos2 = h.z() * h.z();
  const float sin2 = std::fmax(0.f, 1 - cos2), a2 = alpha * alpha;
  const float denom = cos2 * a2 + sin2;  // = cos²θ a² (1 + tan²θ / a²)
  return a2 / (kPi * denom * denom);
}

float Ggx::lambda(const Vec3f& w) const {
  const float cos2 = w.z() * w.z();
  if (cos2 <= 0) return 1e30f;
  const float tan2 = std::fmax(0.f, 1 - cos2) / cos2;
  return (std::sqrt(1 + alpha * alpha * tan2) - 1) / 2;
}

float Ggx::visible_pdf(const Vec3f& wo, const Vec3f& h) const {
  if (wo.z() <= 0) return 0;
  return G1(wo) * std::fmax(0.f, wo.dot(h)) * D(h) / wo.z();
}

Vec3f Ggx::sample_visible(const Vec3f& wo, const Vec2f& u) const {
  // Stretch to the hemisphere configuration, sample a projected disk, unstretch.
  const Vec3f vh = Vec3f(alpha * wo.x(), alpha * wo.y(), wo.z()).normalized();
  const float len2 = vh.x() * vh.x() + vh.y() * vh.y();
  const Vec3f t1 = len2 > 0 ? Vec3f(-vh.y(), vh.x(), 0) / std::sqrt(len2) : Vec3f(1, 0, 0);
  const Vec3f t2 = vh.cross(t1);
  const float r = std::sqrt(u.x()), phi = 2 * kPi * u.y();
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1 + vh.z());
  const float p2 = (1 - s) * std::sqrt(std::fmax(0.f, 1 - p1 * p1)) + s * r * std::sin(phi);
  const Vec3f nh = p1 * t1 + p2 * t2 + std::sqrt(std::fmax(0.f, 1 - p1 * p1 - p2 * p2)) * vh;
  return Vec3f(alpha * nh.x(), alpha * nh.y(), std::fmax(1e-6f, nh.z())).normalized();
}

}  // namespace loom::pathtrace
