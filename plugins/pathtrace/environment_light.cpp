#include "environment_light.hpp"

#include <algorithm>
#include <cmath>

namespace loom::pathtrace {

EnvironmentLight::EnvironmentLight(const Environment& env, Sampling sampling)
    : sampling_(sampling), rotation_(float(env.rotation)) {
  const float k = float(env.intensity);
  color_ = env.color.cast<float>() * k;
  if (env.map && !env.map->empty()) {
    const cv::Mat& m = env.map->pixels;
    width_ = m.cols;
    height_ = m.rows;
    pixels_.resize(std::size_t(width_) * height_);
    const int c = m.channels();
    for (int y = 0; y < height_; ++y) {
      const float* row = m.ptr<float>(y);
      for (int x = 0; x < width_; ++x) {
        const float* p = row + std::size_t(x) * c;
        Vec3f v = c >= 3 ? Vec3f(p[0], p[1], p[2]) : Vec3f::Constant(p[0]);
        // Non-finite or negative texels are dark: a map never injects NaN.
        for (int i = 0; i < 3; ++i) v[i] = std::isfinite(v[i]) && v[i] > 0 ? v[i] * k : 0.f;
        pixels_[std::size_t(y) * width_ + x] = v;
      }
    }
    // Pixel weights luminance · sin θ at the row's center; the mean radiance over
    // the sphere uses the exact solid angle of each row.
    std::vector<double> weights(pixels_.size());
    double total = 0;
    for (int y = 0; y < height_; ++y) {
      const double theta0 = kPi * double(y) / height_, theta1 = kPi * double(y + 1) / height_;
      const double sin_center = std::sin(kPi * (y + 0.5) / height_);
      const double solid = 2 * kPi * (std::cos(theta0) - std::cos(theta1)) / width_;
      for (int x = 0; x < width_; ++x) {
        const double lum = std::max(0.0, double(luminance(pixels_[std::size_t(y) * width_ + x])));
        weights[std::size_t(y) * width_ + x] = lum * sin_center;
        total += lum * solid;
      }
    }
    mean_luminance_ = float(total / (4 * kPi));
    if (sampling_ == Sampling::importance) table_ = AliasTable(weights);
    black_ = !(mean_luminance_ > 0);
    if (sampling_ == Sampling::importance && table_.empty()) black_ = true;
  } else {
    mean_luminance_ = std::max(0.f, luminance(color_));
    black_ = !(mean_luminance_ > 0) && !(color_.array() > 0).any();
  }
}

std::size_t EnvironmentLight::pixel_of(const Vec3f& d, int* row) const {
  const Eigen::Vector2d uv = latlong_uv(d.cast<double>(), rotation_);
  const int x = std::clamp(int(uv.x() * width_), 0, width_ - 1);
  const int y = std::clamp(int(uv.y() * height_), 0, height_ - 1);
  if (row) *row = y;
  return std::size_t(y) * width_ + x;
}

Vec3f EnvironmentLight::radiance(const Vec3f& d) const {
  if (black_) return Vec3f::Zero();
  if (!has_map()) return color_;
  return pixels_[pixel_of(d)];
}

float EnvironmentLight::pdf(const Vec3f& d) const {
  if (black_) return 0;
  if (sampling_ == Sampling::uniform || !has_map()) return kUniformSpherePdf;
  const float sin_theta = std::sqrt(std::fmax(0.f, 1 - d.y() * d.y()));
  if (!(sin_theta > 0)) return 0;
  // Eq. 64.
  return table_.pmf(pixel_of(d)) * float(width_) * float(height_) / (2 * kPi * kPi * sin_theta);
}

EnvironmentLight::Sample EnvironmentLight::sample(float uc, const Vec2f& u) const {
  if (sampling_ == Sampling::uniform || !has_map()) {
    const Vec3f d = sample_uniform_sphere(u);
    return {d, kUniformSpherePdf};
  }
  const std::uint32_t pixel = table_.sample(uc);
  const int x = int(pixel % width_), y = int(pixel / width_);
  const Eigen::Vector2d uv((x + double(u.x())) / width_, (y + double(u.y())) / height_);
  const Vec3f d = latlong_direction(uv, rotation_).cast<float>().normalized();
  return {d, pdf(d)};
}

}  // namespace loom::pathtrace
