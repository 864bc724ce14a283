#include "height_maps.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace loom::shading {

namespace {
double smooth_edge(double distance, double bevel) {
  if (bevel <= 0) return distance > 0 ? 1 : 0;
  const double t = std::clamp(distance / bevel, 0.0, 1.0);
  return std::sin(t * M_PI / 2);  // a rounded (quarter-sine) profile
}
}  // namespace

cv::Mat brick_height(int width, int height, int rows, int columns, double mortar, double bevel,
                     const std::function<void()>& check) {
  cv::Mat h(height, width, CV_32FC1);
  tbb::parallel_for(0, height, [&](int y) {
    if (check) check();
    for (int x = 0; x < width; ++x) {
      // Brick coordinates: one unit per brick height (course) and per brick length.
      const double v = (y + 0.5) / height * rows;
      const int course = static_cast<int>(std::floor(v));
      double u = (x + 0.5) / width * columns + (course % 2 ? 0.5 : 0.0);
      u -= std::floor(u);
      const double fv = v - course;
      // Distance to the nearest joint, in brick heights (a brick is columns/rows
      // heights long in the image's aspect).
      const double length = static_cast<double>(width) / columns / (static_cast<double>(height) / rows);
      const double dv = std::min(fv, 1 - fv) - mortar / 2;
      const double du = std::min(u, 1 - u) * length - mortar / 2;
      h.at<float>(y, x) = static_cast<float>(smooth_edge(std::min(du, dv), bevel));
    }
  });
  return h;
}

cv::Mat bump_height(int width, int height, int rows, int columns, const std::function<void()>& check) {
  cv::Mat h(height, width, CV_32FC1);
  tbb::parallel_for(0, height, [&](int y) {
    if (check) check();
    for (int x = 0; x < width; ++x) {
      double u = (x + 0.5) / width * columns, v = (y + 0.5) / height * rows;
      u = u - std::floor(u) - 0.5;
      v = v - std::floor(v) - 0.5;
      const double r = std::min(1.0, 2 * std::sqrt(u * u + v * v));
      h.at<float>(y, x) = static_cast<float>(0.5 + 0.5 * std::cos(M_PI * r));
    }
  });
  return h;
}

cv::Mat height_to_normal_map(const cv::Mat& height, double strength, bool wrap, const std::function<void()>& check) {
  const int W = height.cols, H = height.rows;
  cv::Mat n(H, W, CV_32FC3);
  tbb::parallel_for(0, H, [&](int y) {
    if (check) check();
    for (int x = 0; x < W; ++x) {
      auto at = [&](int xx, int yy) {
        if (wrap) {
          xx = (xx % W + W) % W;
          yy = (yy % H + H) % H;
        } else {
          xx = std::clamp(xx, 0, W - 1);
          yy = std::clamp(yy, 0, H - 1);
        }
        return static_cast<double>(height.at<float>(yy, xx));
      };
      // Per unit of UV: the image spans [0,1]; rows go down while v goes up.
      const int x0 = wrap ? x - 1 : std::max(x - 1, 0), x1 = wrap ? x + 1 : std::min(x + 1, W - 1);
      const int y0 = wrap ? y - 1 : std::max(y - 1, 0), y1 = wrap ? y + 1 : std::min(y + 1, H - 1);
      const double hu = (at(x1, y) - at(x0, y)) / std::max(x1 - x0, 1) * W;
      const double hv = -(at(x, y1) - at(x, y0)) / std::max(y1 - y0, 1) * H;
      double nx = -strength * hu, ny = -strength * hv, nz = 1;
      const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
      nx /= len, ny /= len, nz /= len;
      n.at<cv::Vec3f>(y, x) = cv::Vec3f(float(0.5 * nx + 0.5), float(0.5 * ny + 0.5), float(0.5 * nz + 0.5));
    }
  });
  return n;
}

}  // namespace loom::shading
