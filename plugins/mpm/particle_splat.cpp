#include "particle_splat.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace loom::mpm {
namespace {

void disc(cv::Mat& image, double cx, double cy, double r, const Eigen::Vector3f& c) {
  const int x0 = std::max(0, static_cast<int>(std::floor(cx - r - 1)));
  const int x1 = std::min(image.cols - 1, static_cast<int>(std::ceil(cx + r + 1)));
  const int y0 = std::max(0, static_cast<int>(std::floor(cy - r - 1)));
  const int y1 = std::min(image.rows - 1, static_cast<int>(std::ceil(cy + r + 1)));
  for (int y = y0; y <= y1; ++y) {
    auto* row = image.ptr<cv::Vec3f>(y);
    for (int x = x0; x <= x1; ++x) {
      // Coverage of the pixel (centre x + 0.5) by the disc, linear in the distance.
      const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
      const float a = static_cast<float>(std::clamp(r + 0.5 - d, 0.0, 1.0));
      if (a <= 0) continue;
      for (int k = 0; k < 3; ++k) row[x][k] += a * (c[k] - row[x][k]);
    }
  }
}

}  // namespace

cv::Mat splat(const MpmState& state, const SplatOptions& o) {
  cv::Mat image(o.width, o.width, CV_32FC3,
                cv::Scalar(o.background[0], o.background[1], o.background[2]));
  const double scale = o.width / o.size;
  if (state.dim == 2) {
    const auto& ps = state.p2;
    for (int i = 0; i < ps.size(); ++i)
      disc(image, ps.x[i][0] * scale, (o.size - ps.x[i][1]) * scale, o.radius_px, ps.color[i]);
    return image;
  }
  // Screen axes (u right, w up) and depth (towards the viewer) for each view.
  int u = 0, w = 1, depth = 2;
  if (o.view == View::top) u = 0, w = 2, depth = 1;
  if (o.view == View::side) u = 2, w = 1, depth = 0;
  const auto& ps = state.p3;
  std::vector<int> order(static_cast<std::size_t>(ps.size()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return ps.x[a][depth] < ps.x[b][depth];
  });
  for (int i : order) {
    // Shade by depth so the solid reads as one: nearer is brighter.
    const float shade = static_cast<float>(0.55 + 0.45 * std::clamp(ps.x[i][depth] / o.size, 0.0, 1.0));
    const double sx = (o.view == View::side ? (o.size - ps.x[i][u]) : ps.x[i][u]) * scale;
    const double sy = (o.view == View::top ? ps.x[i][w] : (o.size - ps.x[i][w])) * scale;
    disc(image, sx, sy, o.radius_px, ps.color[i] * shade);
  }
  return image;
}

}  // namespace loom::mpm
