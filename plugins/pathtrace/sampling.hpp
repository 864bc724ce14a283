// Random streams and the small warps every estimator here uses (pbrt-v4,
// "Sampling Algorithms"): each maps uniform numbers in [0, 1) to a density
// that is returned beside it, so a test can check the two agree.
#pragma once

#include <cmath>
#include <cstdint>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace loom::pathtrace {

using Vec2f = Eigen::Vector2f;
using Vec3f = Eigen::Vector3f;

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 1 / kPi;
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

// One random stream per (seed, pixel, sample): the numbers a sample draws do
// not depend on which thread draws them or on how samples are batched.
class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample)
      : state_(mix(seed ^ mix(pixel * 0x9e3779b97f4a7c15ull + mix(sample + 1)))) {}
  std::uint64_t next_u64() { return mix(state_ += 0x9e3779b97f4a7c15ull); }  // splitmix64
  // 24 random bits: at most 1 - 2^-24, so always below 1 (no clamp needed).
  float uniform() { return float(next_u64() >> 40) * 0x1p-24f; }
  // Two numbers from disjoint bits of one draw (48 of its 64).
  Vec2f uniform2() {
    const std::uint64_t b = next_u64();
    return {float(b >> 40) * 0x1p-24f, float((b >> 16) & 0xffffffu) * 0x1p-24f};
  }

  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_;
};

// cos and sin of 2π t for t in [0, 1), inline (libm's sincosf is a call that
// spills every live SSE register of the path loop around it). The quadrant
// q = round(4t) and 4t - q are exact in float; a = 2π t - qπ/2 in
// [-π/4, π/4] goes through Taylor polynomials whose truncation error there is
// below 3e-8: within 2e-7 of std::cos / std::sin (tested in bsdf_test).
inline void cos_sin_2pi(float t, float* c, float* s) {
  const int q = int(4 * t + 0.5f);  // t >= 0: truncation rounds
  const float a = (4 * t - float(q)) * (kPi / 2);
  const float a2 = a * a;
  const float sa = a * (1 + a2 * (-1.f / 6 + a2 * (1.f / 120 + a2 * (-1.f / 5040 + a2 * (1.f / 362880)))));
  const float ca = 1 + a2 * (-0.5f + a2 * (1.f / 24 + a2 * (-1.f / 720 + a2 * (1.f / 40320 - a2 * (1.f / 3628800)))));
  switch (q & 3) {
    case 0: *c = ca, *s = sa; break;
    case 1: *c = -sa, *s = ca; break;
    case 2: *c = -ca, *s = -sa; break;
    default: *c = sa, *s = -ca; break;
  }
}

// Cosine-weighted hemisphere about +z by Malley's method: pdf = cos(theta) / pi.
inline Vec3f sample_cosine_hemisphere(const Vec2f& u) {
  const float r = std::sqrt(u.x()), z2 = 1 - u.x();  // u.x() < 1: z2 > 0
  float c, s;
  cos_sin_2pi(u.y(), &c, &s);
  return {r * c, r * s, std::sqrt(z2)};
}
inline float cosine_hemisphere_pdf(float cos_theta) { return std::fmax(cos_theta, 0.f) * kInvPi; }

// Uniform over the unit sphere: pdf = 1 / (4 pi).
inline Vec3f sample_uniform_sphere(const Vec2f& u) {
  const float z = 1 - 2 * u.x(), r2 = 1 - z * z, r = std::sqrt(r2 > 0 ? r2 : 0.f);
  float c, s;
  cos_sin_2pi(u.y(), &c, &s);
  return {r * c, r * s, z};
}
constexpr float kUniformSpherePdf = 1 / (4 * kPi);

// Uniform over a triangle, as barycentric weights of its 2nd and 3rd corners
// (Heitz 2019's low-distortion map would do too; this is the square-root one).
inline Vec2f sample_uniform_triangle(const Vec2f& u) {
  const float s = std::sqrt(u.x());
  return {s * (1 - u.y()), s * u.y()};
}

// Veach 1997, eq. 9.13: the power heuristic with beta = 2, for one sample
// from each of two strategies.
inline float power_heuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  if (!(a > 0)) return 0;
  if (std::isinf(a)) return 1;
  return a / (a + b);
}

// 1 / sqrt(x) for x > 0 (finite, normal): the SSE estimate refined by one
// Newton step, relative error below 5e-7 (tested in bsdf_test). A sqrt and a
// division in a row are ~30 cycles of latency, three times per bounce; this
// took ~5 % off the path loop's own time (docs/pathtrace.md, session 3).
inline float inv_sqrt(float x) {
#if defined(__SSE__)
  const float r = _mm_cvtss_f32(_mm_rsqrt_ss(_mm_set_ss(x)));
  return r * (1.5f - 0.5f * x * r * r);
#else
  return 1 / std::sqrt(x);
#endif
}

// v / |v|; v nonzero and finite.
inline Vec3f unit(const Vec3f& v) { return v * inv_sqrt(v.squaredNorm()); }

inline float luminance(const Vec3f& c) { return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z(); }

// An orthonormal frame about a unit normal (Duff et al. 2017).
struct Frame {
  Vec3f s, t, n;
  explicit Frame(const Vec3f& normal) : n(normal) {
    const float sign = std::copysign(1.f, n.z());
    const float a = -1 / (sign + n.z()), b = n.x() * n.y() * a;
    s = {1 + sign * n.x() * n.x() * a, sign * b, -sign * n.x()};
    t = {b, sign + n.y() * n.y() * a, -n.y()};
  }
  Vec3f to_local(const Vec3f& v) const { return {v.dot(s), v.dot(t), v.dot(n)}; }
  Vec3f to_world(const Vec3f& v) const { return v.x() * s + v.y() * t + v.z() * n; }
};

}  // namespace loom::pathtrace
