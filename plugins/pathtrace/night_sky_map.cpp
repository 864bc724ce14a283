#include "night_sky_map.hpp"

#include <cmath>
#include <random>

#include "loom/scene.hpp"

namespace loom::pathtrace {

Image night_sky_map(const NightSkyOptions& o) {
  cv::Mat m(o.height, o.width, CV_32FC3);
  const Eigen::Vector3d moon = latlong_direction(
      {o.moon_azimuth / (2 * M_PI) + 0.5, (M_PI / 2 - o.moon_elevation) / M_PI});
  const double cos_moon = std::cos(o.moon_radius);
  const Eigen::Vector3d horizon(0.55, 0.65, 1.0), zenith(0.2, 0.25, 0.6), ground(0.25, 0.22, 0.2);
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const Eigen::Vector3d d = latlong_direction({(x + 0.5) / o.width, (y + 0.5) / o.height});
      Eigen::Vector3d c;
      if (d.y() >= 0) {
        const double t = std::sqrt(d.y());
        c = o.sky_radiance * ((1 - t) * horizon + t * zenith);
      } else {
        c = o.sky_radiance * 0.3 * ground;
      }
      if (d.dot(moon) >= cos_moon) c = o.moon_radiance * Eigen::Vector3d(1.0, 0.97, 0.9);
      m.at<cv::Vec3f>(y, x) = cv::Vec3f(float(c.x()), float(c.y()), float(c.z()));
    }
  // The pixel holding the moon's center is lit even when the disk is smaller than a pixel.
  const Eigen::Vector2d moon_uv = latlong_uv(moon);
  m.at<cv::Vec3f>(std::min(o.height - 1, int(moon_uv.y() * o.height)),
                  std::min(o.width - 1, int(moon_uv.x() * o.width))) =
      cv::Vec3f(float(o.moon_radiance), float(o.moon_radiance * 0.97), float(o.moon_radiance * 0.9));
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int i = 0; i < o.stars; ++i) {
    // Uniform over the upper hemisphere, brightness spread over two decades.
    const double cos_theta = uni(rng), phi = uni(rng);
    const int x = std::min(o.width - 1, int(phi * o.width));
    const int y = std::min(o.height - 1, int(std::acos(cos_theta) / M_PI * o.height));
    const float b = float(o.sky_radiance * 20 * std::pow(10.0, 2 * uni(rng)));
    m.at<cv::Vec3f>(y, x) = cv::Vec3f(b, b, b * 1.1f);
  }
  return Image(m, Encoding::linear);
}

}  // namespace loom::pathtrace
