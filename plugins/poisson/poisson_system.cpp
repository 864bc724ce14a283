#include "poisson_system.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include "loom/error.hpp"
#include "loom/hash.hpp"

namespace loom::poisson {
namespace {

std::string point_text(cv::Point p) {
  return "[" + std::to_string(p.x) + ", " + std::to_string(p.y) + "]";
}

}  // namespace

BlendRegion place_region(const cv::Mat1b& region, cv::Point offset, cv::Size target) {
  if (cv::countNonZero(region) == 0) throw Error("mask is empty: nothing to blend");
  cv::Mat1b inside = region.clone();
  inside.row(0).setTo(0);
  inside.row(inside.rows - 1).setTo(0);
  inside.col(0).setTo(0);
  inside.col(inside.cols - 1).setTo(0);
  const int requested = cv::countNonZero(region), kept = cv::countNonZero(inside);
  if (kept == 0)
    throw Error("the region lies only on the source's border pixels, where its gradient is "
                "undefined: draw it at least one pixel inside the source");

  BlendRegion r;
  r.clipped_source = kept < requested;
  const cv::Rect target_rect({0, 0}, target);
  const cv::Rect placed = cv::boundingRect(inside) + offset;
  const cv::Rect inner = placed & target_rect;
  if (inner.empty())
    throw Error("the region lands outside the target (offset " + point_text(offset) +
                ", target " + std::to_string(target.width) + "x" + std::to_string(target.height) +
                "): choose an offset that puts it on the target");
  r.rect = cv::Rect(placed.x - 1, placed.y - 1, placed.width + 2, placed.height + 2) & target_rect;
  r.unknown = cv::Mat1b::zeros(r.rect.size());
  for (int y = inner.y; y < inner.br().y; ++y) {
    const uchar* m = inside.ptr<uchar>(y - offset.y);
    uchar* u = r.unknown.ptr<uchar>(y - r.rect.y);
    for (int x = inner.x; x < inner.br().x; ++x)
      if (m[x - offset.x]) {
        u[x - r.rect.x] = 255;
        ++r.count;
      }
  }
  if (r.count == 0)
    throw Error("the region lands outside the target (offset " + point_text(offset) +
                "): choose an offset that puts it on the target");
  r.clipped_target = r.count < kept;
  if (r.count == target_rect.area())
    throw Error("the region covers the whole target: there is no boundary to blend against; "
                "shrink the region or use a larger target");
  return r;
}

std::uint64_t region_key(const BlendRegion& r) {
  Hasher h;
  h.pod(r.rect.width).pod(r.rect.height);
  for (int y = 0; y < r.unknown.rows; ++y) h.bytes(r.unknown.ptr<uchar>(y), r.unknown.cols);
  return h.digest();
}

namespace {

// Row y of b for C channels (a compile-time count, so the channel loops unroll).
template <int C, bool Mixed>
void rhs_row(const BlendRegion& r, const cv::Mat& target, const cv::Mat& source, cv::Point offset,
             int y, float* out) {
  const int w = r.rect.width, h = r.rect.height;
  const uchar* u = r.unknown.ptr<uchar>(y);
  // Rows y − 1, y, y + 1 of f* and g, indexed by grid column times C. Rows of
  // g around an Ω pixel exist: Ω keeps off the source's border.
  const int ty = y + r.rect.y, sy = ty - offset.y;
  const std::ptrdiff_t tx = std::ptrdiff_t(r.rect.x) * C, sx = std::ptrdiff_t(r.rect.x - offset.x) * C;
  const float* f_row[3] = {y > 0 ? target.ptr<float>(ty - 1) + tx : nullptr, target.ptr<float>(ty) + tx,
                           y + 1 < h ? target.ptr<float>(ty + 1) + tx : nullptr};
  const float* g_row[3] = {source.ptr<float>(sy - 1) + sx, source.ptr<float>(sy) + sx,
                           source.ptr<float>(sy + 1) + sx};
  const uchar* u_row[3] = {y > 0 ? r.unknown.ptr<uchar>(y - 1) : nullptr, u,
                           y + 1 < h ? r.unknown.ptr<uchar>(y + 1) : nullptr};
  for (int x = 0; x < w; ++x) {
    if (!u[x]) continue;
    const float* fp = f_row[1] + x * C;
    const float* gp = g_row[1] + x * C;
    float o[C] = {};
    // q ∈ N_p in the order left, right, up, down: (row of q, column of q).
    const int qs[4][2] = {{1, x - 1}, {1, x + 1}, {0, x}, {2, x}};
    for (const auto& q : qs) {
      const int row = q[0], qx = q[1];
      if (qx < 0 || qx >= w || !u_row[row]) continue;  // ∉ N_p: outside the grid
      const float* fq = f_row[row] + qx * C;
      const float* gq = g_row[row] + qx * C;
      const float boundary = u_row[row][qx] ? 0.0f : 1.0f;
      for (int c = 0; c < C; ++c) {
        float v = gp[c] - gq[c];
        if (Mixed && std::abs(fp[c] - fq[c]) > std::abs(v)) v = fp[c] - fq[c];
        o[c] += v + boundary * fq[c];
      }
    }
    for (int c = 0; c < C; ++c) out[x * C + c] = o[c];
  }
}

template <int C>
void rhs_row(const BlendRegion& r, const cv::Mat& target, const cv::Mat& source, cv::Point offset,
             Guidance mode, int y, float* out) {
  if (mode == Guidance::mixed)
    rhs_row<C, true>(r, target, source, offset, y, out);
  else
    rhs_row<C, false>(r, target, source, offset, y, out);
}

}  // namespace

cv::Mat poisson_rhs(const BlendRegion& r, const cv::Mat& target, const cv::Mat& source,
                    cv::Point offset, Guidance mode) {
  const int C = target.channels(), w = r.rect.width;
  CV_Assert(C >= 1 && C <= 4 && source.type() == target.type() && target.depth() == CV_32F);
  cv::Mat b = cv::Mat::zeros(r.rect.size(), CV_MAKETYPE(CV_32F, C));
  tbb::parallel_for(0, r.rect.height, [&](int y) {
    const uchar* u = r.unknown.ptr<uchar>(y);
    if (std::find(u, u + w, uchar(255)) == u + w) return;  // no p ∈ Ω on this row
    float* out = b.ptr<float>(y);
    switch (C) {
      case 1: rhs_row<1>(r, target, source, offset, mode, y, out); break;
      case 2: rhs_row<2>(r, target, source, offset, mode, y, out); break;
      case 3: rhs_row<3>(r, target, source, offset, mode, y, out); break;
      default: rhs_row<4>(r, target, source, offset, mode, y, out); break;
    }
  });
  return b;
}

cv::Mat source_on_rect(const BlendRegion& r, const cv::Mat& source, cv::Point offset) {
  cv::Mat g = cv::Mat::zeros(r.rect.size(), source.type());
  const cv::Rect from = (r.rect - offset) & cv::Rect({0, 0}, source.size());
  if (!from.empty()) source(from).copyTo(g(from + offset - r.rect.tl()));
  return g;
}

}  // namespace loom::poisson
