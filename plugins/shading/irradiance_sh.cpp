#include "irradiance_sh.hpp"

#include <cmath>

#include <opencv2/core.hpp>

#include "loom/scene.hpp"

namespace loom::shading {

std::array<double, 9> sh9_basis(const Eigen::Vector3d& d) {
  const double x = d.x(), y = d.y(), z = d.z();
  return {0.282095,
          0.488603 * y,
          0.488603 * z,
          0.488603 * x,
          1.092548 * x * y,
          1.092548 * y * z,
          0.315392 * (3 * z * z - 1),
          1.092548 * x * z,
          0.546274 * (x * x - y * y)};
}

Sh9 sh9_project(const Image& map, double rotation) {
  constexpr double pi = 3.14159265358979323846;
  cv::Mat px;
  map.pixels.convertTo(px, CV_32F);
  const int W = px.cols, H = px.rows, ch = px.channels();
  Sh9 L;
  L.fill(Eigen::Vector3d::Zero());
  for (int y = 0; y < H; ++y) {
    // A texel spans dphi = 2 pi / W and theta in [y, y + 1] pi / H: its solid
    // angle is dphi (cos theta0 - cos theta1).
    const double solid_angle = 2 * pi / W * (std::cos(pi * y / H) - std::cos(pi * (y + 1) / H));
    const float* row = px.ptr<float>(y);
    for (int x = 0; x < W; ++x) {
      const float* p = row + static_cast<std::size_t>(x) * ch;
      const Eigen::Vector3d radiance = ch < 3 ? Eigen::Vector3d::Constant(p[0]) : Eigen::Vector3d(p[0], p[1], p[2]);
      const auto Y = sh9_basis(latlong_direction({(x + 0.5) / W, (y + 0.5) / H}, rotation));
      for (int k = 0; k < 9; ++k) L[k] += radiance * (Y[k] * solid_angle);
    }
  }
  return L;
}

Sh9 sh9_irradiance_coefficients(const Sh9& radiance) {
  constexpr double pi = 3.14159265358979323846;
  const double A[9] = {pi, 2 * pi / 3, 2 * pi / 3, 2 * pi / 3, pi / 4, pi / 4, pi / 4, pi / 4, pi / 4};
  Sh9 E;
  for (int k = 0; k < 9; ++k) E[k] = radiance[k] * A[k];
  return E;
}

Eigen::Vector3d sh9_irradiance(const Sh9& E, const Eigen::Vector3d& n) {
  const auto Y = sh9_basis(n);
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  for (int k = 0; k < 9; ++k) e += E[k] * Y[k];
  return e;
}

}  // namespace loom::shading
