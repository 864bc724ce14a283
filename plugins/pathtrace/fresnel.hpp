// Fresnel reflectance. Directions in the local frame, normal +z.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "sampling.hpp"

namespace loom::pathtrace {

// Unpolarized reflectance of a dielectric interface (pbrt-v4 eq. 9.5): cos_i
// on the incident side, eta = n_transmitted / n_incident. A negative cos_i
// means the ray arrives from the other side (eta is inverted). 1 under total
// internal reflection.
inline float fresnel_dielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, -1.f, 1.f);
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
  }
  const float sin2_t = (1 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return 1;
  const float cos_t = std::sqrt(std::fmax(0.f, 1 - sin2_t));
  const float r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return (r_par * r_par + r_perp * r_perp) / 2;
}

// Schlick's approximation for conductors with reflectance f0 at normal incidence.
inline Vec3f fresnel_schlick(const Vec3f& f0, float cos_i) {
  const float m = std::pow(std::clamp(1 - std::fabs(cos_i), 0.f, 1.f), 5.f);
  return f0 + (Vec3f::Ones() - f0) * m;
}

inline Vec3f reflect(const Vec3f& wo, const Vec3f& n) { return -wo + 2 * wo.dot(n) * n; }

// Refraction of wo through a surface with normal n (on wo's side), eta =
// n_transmitted / n_incident (pbrt-v4 eq. 9.4); nothing under total internal reflection.
inline std::optional<Vec3f> refract(const Vec3f& wo, const Vec3f& n, float eta) {
  const float cos_i = wo.dot(n);
  const float sin2_t = std::fmax(0.f, 1 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return std::nullopt;
  const float cos_t = std::sqrt(1 - sin2_t);
  return Vec3f(-wo / eta + (cos_i / eta - cos_t) * n);
}

}  // namespace loom::pathtrace
