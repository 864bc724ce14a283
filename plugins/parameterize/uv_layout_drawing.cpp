#include "uv_layout_drawing.hpp"

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

}  // namespace loom::parameterize
