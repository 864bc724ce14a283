// The GGX (Trowbridge-Reitz) microfacet distribution in the local shading
// frame (normal +z), with Heitz 2018's sampling of visible normals.
//   D(h)      = 1 / (pi a² cos⁴θh (1 + tan²θh / a²)²)          (Walter et al. 2007, eq. 33)
//   Λ(w)      = (sqrt(1 + a² tan²θ) - 1) / 2,  G1 = 1 / (1 + Λ)  (Heitz 2014, eq. 86)
//   G(wo, wi) = 1 / (1 + Λ(wo) + Λ(wi))                          (height-correlated)
//   D_wo(h)   = G1(wo) max(0, wo·h) D(h) / cos θo                 (Heitz 2018, eq. 1)
#pragma once

#include "sampling.hpp"

namespace loom::pathtrace {

// Below this alpha a surface is treated as perfectly smooth (a delta lobe).
constexpr float kSmoothAlpha = 1e-3f;

struct Ggx {
  float alpha;  // = roughness², isotropic

  bool smooth() const { return alpha < kSmoothAlpha; }
  float D(const Vec3f& h) const;
  float lambda(const Vec3f& w) const;
  float G1(const Vec3f& w) const { return 1 / (1 + lambda(w)); }
  float G(const Vec3f& wo, const Vec3f& wi) const { return 1 / (1 + lambda(wo) + lambda(wi)); }
  // Density of visible normals seen from wo (wo.z > 0).
  float visible_pdf(const Vec3f& wo, const Vec3f& h) const;
  // A visible normal seen from wo (Heitz 2018, listing 1); wo.z > 0.
  Vec3f sample_visible(const Vec3f& wo, const Vec2f& u) const;
};

}  // namespace loom::pathtrace
