#include "uv_raster.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

namespace loom::parameterize {

cv::Mat draw_uv_layout(const Eigen::MatrixX2d& UV, const Eigen::MatrixX3i& F, int size) {
  cv::Mat canvas(size, size, CV_8UC3, cv::Scalar(255, 255, 255));
  const int shift = 4;  // sub-pixel precision of cv::line and fillConvexPoly
  auto at = [&](int v) {
    return cv::Point(static_cast<int>(std::lround(UV(v, 0) * (size - 1) * (1 << shift))),
                     static_cast<int>(std::lround((1 - UV(v, 1)) * (size - 1) * (1 << shift))));
  };
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector2d a = UV.row(F(f, 1)) - UV.row(F(f, 0)), b = UV.row(F(f, 2)) - UV.row(F(f, 0));
    const bool flipped = a.x() * b.y() - a.y() * b.x() <= 0;
    const cv::Point p[3] = {at(F(f, 0)), at(F(f, 1)), at(F(f, 2))};
    cv::fillConvexPoly(canvas, p, 3, flipped ? cv::Scalar(230, 40, 40) : cv::Scalar(228, 232, 240),
                       cv::LINE_AA, shift);
  }
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      cv::line(canvas, at(F(f, k)), at(F(f, (k + 1) % 3)), cv::Scalar(30, 60, 140), 1, cv::LINE_AA, shift);
  cv::rectangle(canvas, cv::Point(0, 0), cv::Point(size - 1, size - 1), cv::Scalar(0, 0, 0), 1);
  cv::Mat out;
  canvas.convertTo(out, CV_32FC3, 1.0 / 255);
  return out;
}

cv::Mat render_checkered(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::MatrixX2d& UV,
                         int size, int cells, double azimuth, double elevation) {
  const double az = azimuth * M_PI / 180, el = elevation * M_PI / 180;
  const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));  // towards the eye
  const Eigen::Vector3d up0 = std::abs(d.z()) > 0.99 ? Eigen::Vector3d(0, 1, 0) : Eigen::Vector3d(0, 0, 1);
  const Eigen::Vector3d right = up0.cross(d).normalized(), up = d.cross(right);
  Eigen::MatrixX3d P(V.rows(), 3);  // screen x, y, depth (larger = nearer)
  for (int v = 0; v < V.rows(); ++v) P.row(v) << V.row(v).dot(right), V.row(v).dot(up), V.row(v).dot(d);
  const Eigen::Vector2d lo = P.leftCols<2>().colwise().minCoeff(), hi = P.leftCols<2>().colwise().maxCoeff();
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300), scale = 0.9 * size / extent;
  const Eigen::Vector2d centre = (lo + hi) / 2;
  for (int v = 0; v < V.rows(); ++v) {
    P(v, 0) = size / 2.0 + (P(v, 0) - centre.x()) * scale;
    P(v, 1) = size / 2.0 - (P(v, 1) - centre.y()) * scale;
  }
  cv::Mat image(size, size, CV_32FC3, cv::Scalar(1, 1, 1));
  std::vector<double> depth(static_cast<size_t>(size) * size, -std::numeric_limits<double>::infinity());
  for (int f = 0; f < F.rows(); ++f) {
    const int i = F(f, 0), j = F(f, 1), k = F(f, 2);
    const Eigen::Vector3d n = (V.row(j) - V.row(i)).cross(V.row(k) - V.row(i)).transpose();
    if (n.norm() == 0) continue;
    const float shade = static_cast<float>(0.25 + 0.75 * std::abs(n.normalized().dot(d)));
    const double x0 = P(i, 0), y0 = P(i, 1), x1 = P(j, 0), y1 = P(j, 1), x2 = P(k, 0), y2 = P(k, 1);
    const double area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    if (area == 0) continue;
    const int xmin = std::max(0, static_cast<int>(std::floor(std::min({x0, x1, x2}))));
    const int xmax = std::min(size - 1, static_cast<int>(std::ceil(std::max({x0, x1, x2}))));
    const int ymin = std::max(0, static_cast<int>(std::floor(std::min({y0, y1, y2}))));
    const int ymax = std::min(size - 1, static_cast<int>(std::ceil(std::max({y0, y1, y2}))));
    for (int y = ymin; y <= ymax; ++y)
      for (int x = xmin; x <= xmax; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double b0 = ((x1 - px) * (y2 - py) - (x2 - px) * (y1 - py)) / area;
        const double b1 = ((x2 - px) * (y0 - py) - (x0 - px) * (y2 - py)) / area;
        const double b2 = 1 - b0 - b1;
        if (b0 < 0 || b1 < 0 || b2 < 0) continue;
        const double z = b0 * P(i, 2) + b1 * P(j, 2) + b2 * P(k, 2);
        double& zb = depth[static_cast<size_t>(y) * size + x];
        if (z <= zb) continue;
        zb = z;
        const Eigen::Vector2d uv = b0 * UV.row(i) + b1 * UV.row(j) + b2 * UV.row(k);
        const bool dark = (static_cast<long>(std::floor(uv.x() * cells)) +
                           static_cast<long>(std::floor(uv.y() * cells))) % 2 != 0;
        const cv::Vec3f color = dark ? cv::Vec3f(0.15f, 0.3f, 0.6f) : cv::Vec3f(0.95f, 0.95f, 0.95f);
        image.at<cv::Vec3f>(y, x) = color * shade;
      }
  }
  return image;
}

}  // namespace loom::parameterize
