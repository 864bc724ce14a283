// Light from infinitely far away (loom::Environment): a lat-long radiance map
// or a uniform color, with directions drawn either uniformly over the sphere
// or by importance: an alias table over the map's pixels weighted by
// luminance · sin θ, a uniform point within the pixel, and the density
//   p(ω) = w h / (2 π² sin θ) · p_img(i, j)                   (course report, eq. 64)
// (the Jacobian of (u, v) ∈ [0,1]² -> (φ, θ) -> ω is 2π · π · sin θ).
// Lookups are nearest-pixel, so the map is piecewise constant exactly as the
// density assumes.
#pragma once

#include "alias_table.hpp"
#include "loom/scene.hpp"
#include "sampling.hpp"

namespace loom::pathtrace {

class EnvironmentLight {
 public:
  enum class Sampling { importance, uniform };
  EnvironmentLight() = default;
  EnvironmentLight(const Environment& environment, Sampling sampling);

  bool black() const { return black_; }
  bool has_map() const { return width_ > 0; }
  Vec3f radiance(const Vec3f& direction) const;
  // Density over solid angle of sample() drawing this direction.
  float pdf(const Vec3f& direction) const;
  struct Sample {
    Vec3f direction;
    float pdf;
  };
  // uc picks the pixel, u the point within it.
  Sample sample(float uc, const Vec2f& u) const;
  // Mean radiance over the sphere (luminance), for power-weighted light selection.
  float mean_luminance() const { return mean_luminance_; }

 private:
  std::size_t pixel_of(const Vec3f& direction, int* row = nullptr) const;

  bool black_ = true;
  Sampling sampling_ = Sampling::uniform;
  Vec3f color_ = Vec3f::Zero();
  float rotation_ = 0;
  int width_ = 0, height_ = 0;
  std::vector<Vec3f> pixels_;  // radiance, intensity applied
  AliasTable table_;
  float mean_luminance_ = 0;
};

}  // namespace loom::pathtrace
