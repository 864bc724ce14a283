#include "normal_mapping.hpp"

#include <cmath>

#include "loom/numerics/tangent_frames.hpp"

namespace loom::pathtrace {

Vec3f mapped_normal(const Vec3f& n, const Vec3f& dpdu, const Vec3f& dpdv, const Vec3f& texel) {
  Vec3f T, B;
  if (!numerics::tangent_basis(n, dpdu, dpdv, &T, &B)) return n;
  const Vec3f m = 2 * texel - Vec3f::Ones();
  const Vec3f mapped = m.x() * T + m.y() * B + m.z() * n;
  const float length2 = mapped.squaredNorm();
  if (!(length2 > 1e-12f) || !std::isfinite(length2)) return n;
  return mapped / std::sqrt(length2);
}

Vec3f bend_above_horizon(const Vec3f& ns_in, const Vec3f& ng_in, const Vec3f& wo) {
  // Work on wo's side of the geometric surface (the BSDFs are two-sided).
  const float side = wo.dot(ng_in) < 0 ? -1.f : 1.f;
  const Vec3f ns = side * ns_in, ng = side * ng_in;
  const float og = wo.dot(ng);
  if (!(og > 0)) return ns_in;  // grazing exactly: nothing to keep above
  // Keep wo at least this far above the bent horizon.
  const float target = std::fmin(0.01f, 0.5f * og);
  const float on = wo.dot(ns);
  if (on >= target) return ns_in;
  // wo·(ns + k ng) = target: k >= 0 since on < target; after normalizing the
  // cosine stays positive.
  const float k = (target - on) / og;
  const Vec3f bent = ns + k * ng;
  const float length2 = bent.squaredNorm();
  if (!(length2 > 1e-12f) || !std::isfinite(length2)) return ng_in;
  return side * bent / std::sqrt(length2);
}

}  // namespace loom::pathtrace
