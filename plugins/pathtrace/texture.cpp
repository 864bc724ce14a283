#include "texture.hpp"

#include <algorithm>
#include <cmath>

namespace loom::pathtrace {

namespace {

Vec3f read(const cv::Mat& m, int x, int y) {
  const float* p = m.ptr<float>(y) + std::size_t(x) * m.channels();
  return m.channels() >= 3 ? Vec3f(p[0], p[1], p[2]) : Vec3f::Constant(p[0]);
}

float wrap01(float t) { return std::isfinite(t) ? t - std::floor(t) : 0.f; }

}  // namespace

Vec3f texel_color(const Image& image, const Vec2f& uv) {
  const cv::Mat& m = image.pixels;
  const float u = wrap01(uv.x()), v = wrap01(uv.y());
  const int x = std::clamp(int(u * m.cols), 0, m.cols - 1);
  const int y = std::clamp(int((1 - v) * m.rows), 0, m.rows - 1);
  Vec3f c = read(m, x, y);
  for (int i = 0; i < 3; ++i) c[i] = std::isfinite(c[i]) ? std::max(c[i], 0.f) : 0.f;
  return c;
}

Vec3f texel_bilinear(const Image& image, const Vec2f& uv) {
  const cv::Mat& m = image.pixels;
  // Continuous texel coordinates with texel centres at integers + 1/2.
  const float fx = wrap01(uv.x()) * float(m.cols) - 0.5f;
  const float fy = (1 - wrap01(uv.y())) * float(m.rows) - 0.5f;
  const float x0f = std::floor(fx), y0f = std::floor(fy);
  const float ax = fx - x0f, ay = fy - y0f;
  auto wrap = [](int i, int n) { return ((i % n) + n) % n; };
  const int x0 = wrap(int(x0f), m.cols), x1 = wrap(int(x0f) + 1, m.cols);
  const int y0 = wrap(int(y0f), m.rows), y1 = wrap(int(y0f) + 1, m.rows);
  return (1 - ay) * ((1 - ax) * read(m, x0, y0) + ax * read(m, x1, y0)) +
         ay * ((1 - ax) * read(m, x0, y1) + ax * read(m, x1, y1));
}

}  // namespace loom::pathtrace
