#include "warp_image.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace loom::warp {

namespace {

constexpr int kRowsPerBlock = 64;  // progress and cancellation granularity

// Runs body(i) for rows [0, rows) in parallel, in blocks, reporting between.
void for_rows(int rows, const std::function<void(int)>& body, const RowProgress& progress) {
  for (int start = 0; start < rows; start += kRowsPerBlock) {
    const int end = std::min(rows, start + kRowsPerBlock);
    tbb::parallel_for(tbb::blocked_range<int>(start, end), [&](const tbb::blocked_range<int>& r) {
      for (int i = r.begin(); i != r.end(); ++i) body(i);
    });
    if (progress) progress(end, rows);
  }
}

// Grid positions of the exact samples along one axis: 0, s, 2s, ..., n − 1.
std::vector<int> sample_positions(int n, int step) {
  std::vector<int> s;
  for (int k = 0; k < n - 1; k += step) s.push_back(k);
  s.push_back(n - 1);
  return s;
}

template <int C>
void sample_row(const cv::Mat& src, const double* fx, const double* fy, int n, float* out,
                Outside outside, const float* background) {
  const int w = src.cols, h = src.rows;
  for (int j = 0; j < n; ++j, out += C) {
    double sx = fx[j], sy = fy[j];
    const bool inside = sx >= 0 && sx <= w && sy >= 0 && sy <= h;  // false for NaN too
    if (!inside && (outside == Outside::background || !(std::isfinite(sx) && std::isfinite(sy)))) {
      for (int c = 0; c < C; ++c) out[c] = background[c];
      continue;
    }
    sx = std::clamp(sx - 0.5, 0.0, w - 1.0);
    sy = std::clamp(sy - 0.5, 0.0, h - 1.0);
    const int x0 = std::min(static_cast<int>(sx), w - 1), y0 = std::min(static_cast<int>(sy), h - 1);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const float tx = static_cast<float>(sx - x0), ty = static_cast<float>(sy - y0);
    const float* r0 = src.ptr<float>(y0);
    const float* r1 = src.ptr<float>(y1);
    for (int c = 0; c < C; ++c) {
      const float top = r0[x0 * C + c] + tx * (r0[x1 * C + c] - r0[x0 * C + c]);
      const float bottom = r1[x0 * C + c] + tx * (r1[x1 * C + c] - r1[x0 * C + c]);
      out[c] = top + ty * (bottom - top);
    }
  }
}

}  // namespace

void map_rows(const RowMap& f, cv::Size size, int step,
              const std::function<void(int, const double*, const double*)>& body,
              const RowProgress& progress) {
  const int w = size.width, h = size.height;
  std::vector<double> centers(static_cast<std::size_t>(w));
  for (int j = 0; j < w; ++j) centers[static_cast<std::size_t>(j)] = j + 0.5;
  if (step <= 1) {
    for_rows(h, [&](int i) {
      std::vector<double> fx(static_cast<std::size_t>(w)), fy(static_cast<std::size_t>(w));
      f(i + 0.5, centers.data(), w, fx.data(), fy.data());
      body(i, fx.data(), fy.data());
    }, progress);
    return;
  }
  // f exactly on a coarse lattice, then bilinear interpolation per row.
  const std::vector<int> xs = sample_positions(w, step), ys = sample_positions(h, step);
  const int nx = static_cast<int>(xs.size()), ny = static_cast<int>(ys.size());
  std::vector<double> lx(static_cast<std::size_t>(nx));
  for (int a = 0; a < nx; ++a) lx[static_cast<std::size_t>(a)] = xs[static_cast<std::size_t>(a)] + 0.5;
  cv::Mat gx(ny, nx, CV_64F), gy(ny, nx, CV_64F);
  tbb::parallel_for(0, ny, [&](int b) {
    f(ys[static_cast<std::size_t>(b)] + 0.5, lx.data(), nx, gx.ptr<double>(b), gy.ptr<double>(b));
  });
  for_rows(h, [&](int i) {
    const int b = std::min(i / step, ny - 2 < 0 ? 0 : ny - 2);
    const int b1 = std::min(b + 1, ny - 1);
    const double ty = b1 == b ? 0.0 : double(i - ys[static_cast<std::size_t>(b)]) /
                                          (ys[static_cast<std::size_t>(b1)] - ys[static_cast<std::size_t>(b)]);
    std::vector<double> fx(static_cast<std::size_t>(w)), fy(static_cast<std::size_t>(w));
    for (int j = 0; j < w; ++j) {
      const int a = std::min(j / step, nx - 2 < 0 ? 0 : nx - 2);
      const int a1 = std::min(a + 1, nx - 1);
      const double tx = a1 == a ? 0.0 : double(j - xs[static_cast<std::size_t>(a)]) /
                                            (xs[static_cast<std::size_t>(a1)] - xs[static_cast<std::size_t>(a)]);
      auto lerp2 = [&](const cv::Mat& g) {
        const double top = g.at<double>(b, a) + tx * (g.at<double>(b, a1) - g.at<double>(b, a));
        const double bot = g.at<double>(b1, a) + tx * (g.at<double>(b1, a1) - g.at<double>(b1, a));
        return top + ty * (bot - top);
      };
      fx[static_cast<std::size_t>(j)] = lerp2(gx);
      fy[static_cast<std::size_t>(j)] = lerp2(gy);
    }
    body(i, fx.data(), fy.data());
  }, progress);
}

cv::Mat inverse_warp(const cv::Mat& source, const RowMap& to_source, cv::Size size, int step,
                     Outside outside, const cv::Scalar& background, const RowProgress& progress) {
  CV_Assert(source.depth() == CV_32F && source.channels() >= 1 && source.channels() <= 4);
  cv::Mat out(size, source.type());
  const float bg[4] = {float(background[0]), float(background[1]), float(background[2]), float(background[3])};
  const int C = source.channels();
  map_rows(to_source, size, step, [&](int i, const double* fx, const double* fy) {
    float* row = out.ptr<float>(i);
    switch (C) {
      case 1: sample_row<1>(source, fx, fy, size.width, row, outside, bg); break;
      case 2: sample_row<2>(source, fx, fy, size.width, row, outside, bg); break;
      case 3: sample_row<3>(source, fx, fy, size.width, row, outside, bg); break;
      default: sample_row<4>(source, fx, fy, size.width, row, outside, bg); break;
    }
  }, progress);
  return out;
}

Splat forward_warp(const cv::Mat& source, const RowMap& to_target, cv::Size size, int step,
                   const cv::Scalar& background, const RowProgress& progress) {
  CV_Assert(source.depth() == CV_32F && source.channels() >= 1 && source.channels() <= 4);
  const int w = source.cols, h = source.rows;
  cv::Mat target(h, w, CV_32FC2);
  map_rows(to_target, source.size(), step, [&](int i, const double* fx, const double* fy) {
    float* row = target.ptr<float>(i);
    for (int j = 0; j < w; ++j) {
      const bool finite = std::isfinite(fx[j]) && std::isfinite(fy[j]);
      row[2 * j] = finite ? static_cast<float>(fx[j]) : NAN;
      row[2 * j + 1] = finite ? static_cast<float>(fy[j]) : NAN;
    }
  }, progress);

  Splat s;
  s.image = cv::Mat(size, source.type(), background);
  s.written = cv::Mat::zeros(size, CV_8U);
  const int C = source.channels();
  for (int i = 0; i < h; ++i) {
    const float* t = target.ptr<float>(i);
    const float* t_below = target.ptr<float>(std::min(i + 1, h - 1));
    const float* src = source.ptr<float>(i);
    for (int j = 0; j < w; ++j) {
      const float tx = t[2 * j], ty = t[2 * j + 1];
      if (!(std::isfinite(tx) && std::isfinite(ty))) continue;
      if (j + 1 < w && std::isfinite(t[2 * j + 2]))
        s.max_stretch = std::max(s.max_stretch, double(std::hypot(t[2 * j + 2] - tx, t[2 * j + 3] - ty)));
      if (i + 1 < h && std::isfinite(t_below[2 * j]))
        s.max_stretch = std::max(s.max_stretch, double(std::hypot(t_below[2 * j] - tx, t_below[2 * j + 1] - ty)));
      const double ox = std::floor(tx), oy = std::floor(ty);  // the output pixel containing f(x)
      if (ox < 0 || oy < 0 || ox >= size.width || oy >= size.height) continue;
      float* dst = s.image.ptr<float>(static_cast<int>(oy)) + static_cast<int>(ox) * C;
      for (int c = 0; c < C; ++c) dst[c] = src[j * C + c];
      s.written.at<unsigned char>(static_cast<int>(oy), static_cast<int>(ox)) = 255;
    }
  }
  return s;
}

int fill_cracks(cv::Mat& image, cv::Mat& written, int radius) {
  radius = std::max(radius, 1);
  cv::Mat closed;
  const cv::Mat disk = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
  cv::morphologyEx(written, closed, cv::MORPH_CLOSE, disk, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
  cv::Mat cracks = closed & ~written;
  int filled = 0;
  const int C = image.channels();
  for (int sweep = 0; sweep < 2 * radius && cv::countNonZero(cracks) > 0; ++sweep) {
    cv::Mat known = written.clone();  // this sweep reads only pixels known before it
    std::vector<cv::Point> todo;
    cv::findNonZero(cracks, todo);
    for (const cv::Point& pt : todo) {
      float sum[4] = {0, 0, 0, 0};
      int count = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int y = pt.y + dy, x = pt.x + dx;
          if (y < 0 || x < 0 || y >= image.rows || x >= image.cols || !known.at<unsigned char>(y, x)) continue;
          const float* v = image.ptr<float>(y) + x * C;
          for (int c = 0; c < C; ++c) sum[c] += v[c];
          ++count;
        }
      if (count == 0) continue;
      float* dst = image.ptr<float>(pt.y) + pt.x * C;
      for (int c = 0; c < C; ++c) dst[c] = sum[c] / count;
      written.at<unsigned char>(pt) = 255;
      cracks.at<unsigned char>(pt) = 0;
      ++filled;
    }
  }
  return filled;
}

}  // namespace loom::warp
