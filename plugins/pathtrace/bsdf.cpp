#include "bsdf.hpp"

#include <algorithm>

#include "fresnel.hpp"

namespace loom::pathtrace {

namespace {

using Model = Material::Model;

// Reflection-only models are two-sided: a back-facing wo mirrors both directions.
struct Sided {
  Vec3f wo, wi;
};
Sided upper(const Vec3f& wo, const Vec3f& wi) {
  if (wo.z() >= 0) return {wo, wi};
  return {Vec3f(wo.x(), wo.y(), -wo.z()), Vec3f(wi.x(), wi.y(), -wi.z())};
}
Vec3f flip_like(const Vec3f& w, const Vec3f& wo) {
  return wo.z() >= 0 ? w : Vec3f(w.x(), w.y(), -w.z());
}

float plastic_specular_probability(const SurfaceMaterial& m, float cos_o) {
  const float f = fresnel_dielectric(cos_o, m.ior);
  const float d = (1 - f) * std::fmax(luminance(m.base), 0.f);
  return std::clamp(f / std::fmax(f + d, 1e-6f), 0.05f, 0.95f);
}

// GGX reflection of one lobe: f |cos θi| and the density of wi, both upper.
Vec3f glossy_eval(const Ggx& g, const Vec3f& wo, const Vec3f& wi, const Vec3f& fresnel_f0,
                  float ior, bool dielectric_fresnel) {
  if (wo.z() <= 0 || wi.z() <= 0) return Vec3f::Zero();
  Vec3f h = wo + wi;
  if (h.squaredNorm() == 0) return Vec3f::Zero();
  h.normalize();
  const Vec3f F = dielectric_fresnel ? Vec3f::Constant(fresnel_dielectric(wo.dot(h), ior))
                                     : fresnel_schlick(fresnel_f0, wo.dot(h));
  return F * (g.D(h) * g.G(wo, wi) / (4 * wo.z()));
}
float glossy_pdf(const Ggx& g, const Vec3f& wo, const Vec3f& wi) {
  if (wo.z() <= 0 || wi.z() <= 0) return 0;
  Vec3f h = wo + wi;
  if (h.squaredNorm() == 0) return 0;
  h.normalize();
  return g.visible_pdf(wo, h) / (4 * std::fabs(wo.dot(h)));
}

// The rough dielectric, pbrt-v4's DielectricBxDF::f and ::PDF.
struct DielectricHalfVector {
  Vec3f wm;
  float etap;
  bool reflect;
  bool valid;
};
DielectricHalfVector dielectric_half_vector(const Vec3f& wo, const Vec3f& wi, float eta) {
  const float co = wo.z(), ci = wi.z();
  DielectricHalfVector r{Vec3f::Zero(), 1, co * ci > 0, false};
  if (co == 0 || ci == 0) return r;
  if (!r.reflect) r.etap = co > 0 ? eta : 1 / eta;
  Vec3f wm = wi * r.etap + wo;
  if (wm.squaredNorm() == 0) return r;
  wm.normalize();
  if (wm.z() < 0) wm = -wm;
  if (wm.dot(wi) * ci < 0 || wm.dot(wo) * co < 0) return r;
  r.wm = wm;
  r.valid = true;
  return r;
}

Vec3f rough_dielectric_eval(const SurfaceMaterial& m, const Vec3f& wo, const Vec3f& wi) {
  const auto hv = dielectric_half_vector(wo, wi, m.ior);
  if (!hv.valid) return Vec3f::Zero();
  const float F = fresnel_dielectric(wo.dot(hv.wm), m.ior);
  const float D = m.ggx.D(hv.wm), G = m.ggx.G(wo, wi);
  if (hv.reflect) return Vec3f::Constant(D * G * F / (4 * std::fabs(wo.z())));
  const float denom = wi.dot(hv.wm) + wo.dot(hv.wm) / hv.etap;
  const float ft = D * (1 - F) * G *
                   std::fabs(wi.dot(hv.wm) * wo.dot(hv.wm) / (wo.z() * denom * denom)) /
                   (hv.etap * hv.etap);
  return m.base * ft;
}
float rough_dielectric_pdf(const SurfaceMaterial& m, const Vec3f& wo, const Vec3f& wi) {
  const auto hv = dielectric_half_vector(wo, wi, m.ior);
  if (!hv.valid) return 0;
  const float R = fresnel_dielectric(wo.dot(hv.wm), m.ior), T = 1 - R;
  const Vec3f wo_up = wo.z() >= 0 ? wo : Vec3f(-wo);
  // pbrt-v4's D_wo(wm) with |cos| for a wo inside: the visible normals seen from -wo.
  const float visible = m.ggx.visible_pdf(wo_up, hv.wm);
  if (hv.reflect) return visible / (4 * std::fabs(wo.dot(hv.wm))) * R;
  const float denom = wi.dot(hv.wm) + wo.dot(hv.wm) / hv.etap;
  return visible * std::fabs(wi.dot(hv.wm)) / (denom * denom) * T;
}

std::optional<BsdfSample> dielectric_sample(const SurfaceMaterial& m, const Vec3f& wo, float uc,
                                            const Vec2f& u) {
  if (wo.z() == 0) return std::nullopt;
  if (m.ggx.smooth()) {
    const float R = fresnel_dielectric(wo.z(), m.ior);
    if (uc < R) return BsdfSample{Vec3f(-wo.x(), -wo.y(), wo.z()), Vec3f::Ones(), R, true};
    const float etap = wo.z() > 0 ? m.ior : 1 / m.ior;
    const auto wi = refract(wo, Vec3f(0, 0, wo.z() > 0 ? 1.f : -1.f), etap);
    if (!wi) return std::nullopt;
    return BsdfSample{*wi, m.base / (etap * etap), 1 - R, true};
  }
  // A visible normal (in the upper hemisphere, as seen from wo or -wo), then
  // reflection or refraction chosen by F.
  const Vec3f wo_up = wo.z() > 0 ? wo : Vec3f(-wo);
  const Vec3f wm = m.ggx.sample_visible(wo_up, u);
  const float R = fresnel_dielectric(wo.dot(wm), m.ior);
  Vec3f wi;
  if (uc < R) {
    wi = reflect(wo, wm);
    if (wi.z() * wo.z() <= 0) return std::nullopt;
  } else {
    const float etap = wo.dot(wm) > 0 ? m.ior : 1 / m.ior;
    const Vec3f n = wo.dot(wm) > 0 ? wm : Vec3f(-wm);
    const auto t = refract(wo, n, etap);
    if (!t || t->z() * wo.z() >= 0) return std::nullopt;
    wi = *t;
  }
  const float pdf = rough_dielectric_pdf(m, wo, wi);
  if (!(pdf > 0)) return std::nullopt;
  return BsdfSample{wi, rough_dielectric_eval(m, wo, wi) / pdf, pdf, false};
}

}  // namespace

Vec3f bsdf_eval(const SurfaceMaterial& m, const Vec3f& wo_in, const Vec3f& wi_in) {
  if (m.model == Model::dielectric)
    return m.ggx.smooth() ? Vec3f::Zero() : rough_dielectric_eval(m, wo_in, wi_in);
  const auto [wo, wi] = upper(wo_in, wi_in);
  if (wi.z() <= 0 || wo.z() <= 0) return Vec3f::Zero();
  switch (m.model) {
    case Model::diffuse:
      return m.base * (kInvPi * wi.z());
    case Model::conductor:
      return m.ggx.smooth() ? Vec3f::Zero() : glossy_eval(m.ggx, wo, wi, m.base, m.ior, false);
    case Model::plastic: {
      const float t = (1 - fresnel_dielectric(wo.z(), m.ior)) * (1 - fresnel_dielectric(wi.z(), m.ior));
      Vec3f f = m.base * (t * kInvPi * wi.z());
      if (!m.ggx.smooth()) f += glossy_eval(m.ggx, wo, wi, Vec3f::Zero(), m.ior, true);
      return f;
    }
    default:
      return Vec3f::Zero();
  }
}

float bsdf_pdf(const SurfaceMaterial& m, const Vec3f& wo_in, const Vec3f& wi_in) {
  if (m.model == Model::dielectric)
    return m.ggx.smooth() ? 0.f : rough_dielectric_pdf(m, wo_in, wi_in);
  const auto [wo, wi] = upper(wo_in, wi_in);
  if (wi.z() <= 0 || wo.z() <= 0) return 0;
  switch (m.model) {
    case Model::diffuse:
      return cosine_hemisphere_pdf(wi.z());
    case Model::conductor:
      return m.ggx.smooth() ? 0.f : glossy_pdf(m.ggx, wo, wi);
    case Model::plastic: {
      const float ps = plastic_specular_probability(m, wo.z());
      return (1 - ps) * cosine_hemisphere_pdf(wi.z()) +
             (m.ggx.smooth() ? 0.f : ps * glossy_pdf(m.ggx, wo, wi));
    }
    default:
      return 0;
  }
}

std::optional<BsdfSample> bsdf_sample(const SurfaceMaterial& m, const Vec3f& wo_in, float uc,
                                      const Vec2f& u) {
  if (m.model == Model::dielectric) return dielectric_sample(m, wo_in, uc, u);
  const Vec3f wo = wo_in.z() >= 0 ? wo_in : Vec3f(wo_in.x(), wo_in.y(), -wo_in.z());
  if (wo.z() <= 0) return std::nullopt;
  Vec3f wi;
  switch (m.model) {
    case Model::diffuse:
      wi = sample_cosine_hemisphere(u);
      break;
    case Model::conductor:
      if (m.ggx.smooth())
        return BsdfSample{flip_like(Vec3f(-wo.x(), -wo.y(), wo.z()), wo_in),
                          fresnel_schlick(m.base, wo.z()), 1, true};
      wi = reflect(wo, m.ggx.sample_visible(wo, u));
      break;
    case Model::plastic: {
      const float ps = plastic_specular_probability(m, wo.z());
      if (uc < ps) {
        if (m.ggx.smooth())
          return BsdfSample{flip_like(Vec3f(-wo.x(), -wo.y(), wo.z()), wo_in),
                            Vec3f::Constant(fresnel_dielectric(wo.z(), m.ior) / ps), ps, true};
        wi = reflect(wo, m.ggx.sample_visible(wo, u));
      } else {
        wi = sample_cosine_hemisphere(u);
      }
      break;
    }
    default:
      return std::nullopt;
  }
  if (wi.z() <= 0) return std::nullopt;
  wi = flip_like(wi, wo_in);
  const float pdf = bsdf_pdf(m, wo_in, wi);
  if (!(pdf > 0)) return std::nullopt;
  return BsdfSample{wi, bsdf_eval(m, wo_in, wi) / pdf, pdf, false};
}

}  // namespace loom::pathtrace
