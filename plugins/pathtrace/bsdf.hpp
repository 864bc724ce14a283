// Scattering by the four material models of loom::Material, in the local
// shading frame (normal +z, pointing out of the object by its winding).
// Directions point away from the surface; values include the cosine:
//   eval = f(wo, wi) |cos θi|,  sample().weight = f |cos θi| / pdf.
//   diffuse     Lambert, albedo base
//   conductor   GGX (microfacet.hpp), Schlick F0 = base; alpha < kSmoothAlpha: a mirror
//   dielectric  GGX reflection + transmission (Walter et al. 2007, pbrt-v4's DielectricBxDF),
//               transmission tinted by base and scaled by 1/eta² (radiance); smooth: delta lobes
//   plastic     a dielectric coat of index ior over a Lambert base (a two-lobe mixture:
//               GGX coat reflection + (1 - F(wo))(1 - F(wi)) base / pi)
#pragma once

#include <optional>

#include "loom/scene.hpp"
#include "microfacet.hpp"

namespace loom::pathtrace {

struct SurfaceMaterial {
  Material::Model model = Material::Model::diffuse;
  Vec3f base{0.8f, 0.8f, 0.8f};
  Ggx ggx{0.25f};
  float ior = 1.5f;

  // Only delta lobes: light sampling cannot help.
  bool purely_specular() const {
    return ggx.smooth() && (model == Material::Model::conductor || model == Material::Model::dielectric);
  }
};

struct BsdfSample {
  Vec3f wi;
  Vec3f weight;  // f |cos θi| / pdf
  float pdf;     // solid-angle density, or the lobe's probability for a delta lobe
  bool delta;
};

Vec3f bsdf_eval(const SurfaceMaterial& m, const Vec3f& wo, const Vec3f& wi);
float bsdf_pdf(const SurfaceMaterial& m, const Vec3f& wo, const Vec3f& wi);
// uc picks a lobe, u the direction within it.
std::optional<BsdfSample> bsdf_sample(const SurfaceMaterial& m, const Vec3f& wo, float uc,
                                      const Vec2f& u);

}  // namespace loom::pathtrace
