#include "polygon_fill.hpp"

#include <algorithm>
#include <cmath>

namespace loom::draw {

namespace {

struct Edge {
  double y0, y1;    // y0 < y1
  double x0, dxdy;  // x at y0, slope
  int winding;      // +1 downwards, −1 upwards
};

struct Crossing {
  double x;
  int winding;
};

bool inside(int winding, FillRule rule) { return rule == FillRule::nonzero ? winding != 0 : (winding & 1) != 0; }

// Adds weight w times the length of [a, b) ∩ [j, j + 1) to cov[j], exactly.
void add_span(std::vector<double>& cov, double a, double b, double w) {
  const int width = static_cast<int>(cov.size()) - 1;  // one extra slot for the difference array
  a = std::clamp(a, 0.0, double(width));
  b = std::clamp(b, 0.0, double(width));
  if (b <= a) return;
  const int ja = static_cast<int>(a), jb = static_cast<int>(b);
  if (ja == jb) {
    cov[static_cast<std::size_t>(ja)] += (b - a) * w;
    return;
  }
  cov[static_cast<std::size_t>(ja)] += (ja + 1 - a) * w;
  for (int j = ja + 1; j < jb; ++j) cov[static_cast<std::size_t>(j)] += w;
  if (jb < width) cov[static_cast<std::size_t>(jb)] += (b - jb) * w;
}

}  // namespace

cv::Mat polygon_coverage(const std::vector<Eigen::Vector2d>& polygon, cv::Size size, FillRule rule,
                         bool antialias) {
  cv::Mat out = cv::Mat::zeros(size, CV_32F);
  const std::size_t n = polygon.size();
  if (n < 3) return out;
  std::vector<Edge> edges;
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector2d& a = polygon[k];
    const Eigen::Vector2d& b = polygon[(k + 1) % n];
    if (!a.allFinite() || !b.allFinite() || a.y() == b.y()) continue;  // horizontal edges cross no scan-line
    const bool down = b.y() > a.y();
    const Eigen::Vector2d& top = down ? a : b;
    const Eigen::Vector2d& bottom = down ? b : a;
    edges.push_back({top.y(), bottom.y(), top.x(), (bottom.x() - top.x()) / (bottom.y() - top.y()), down ? 1 : -1});
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& l, const Edge& r) { return l.y0 < r.y0; });

  const int samples = antialias ? 16 : 1;
  std::vector<const Edge*> active;
  std::vector<Crossing> crossings;
  std::vector<double> cov(static_cast<std::size_t>(size.width) + 1);
  std::size_t next = 0;
  for (int i = 0; i < size.height; ++i) {
    // Active edges: those overlapping the row [i, i + 1).
    while (next < edges.size() && edges[next].y0 < i + 1) active.push_back(&edges[next++]);
    active.erase(std::remove_if(active.begin(), active.end(), [i](const Edge* e) { return e->y1 <= i; }),
                 active.end());
    if (active.empty()) continue;
    std::fill(cov.begin(), cov.end(), 0.0);
    for (int s = 0; s < samples; ++s) {
      const double y = i + (s + 0.5) / samples;
      crossings.clear();
      for (const Edge* e : active)
        if (e->y0 <= y && y < e->y1) crossings.push_back({e->x0 + (y - e->y0) * e->dxdy, e->winding});
      std::sort(crossings.begin(), crossings.end(), [](const Crossing& l, const Crossing& r) { return l.x < r.x; });
      int winding = 0;
      for (std::size_t c = 0; c + 1 < crossings.size(); ++c) {
        winding += crossings[c].winding;
        if (!inside(winding, rule)) continue;
        const double a = crossings[c].x, b = crossings[c + 1].x;
        if (antialias) {
          add_span(cov, a, b, 1.0 / samples);
        } else {  // pixel centers j + 0.5 in [a, b)
          const int j0 = std::max(0, static_cast<int>(std::ceil(a - 0.5)));
          const int j1 = std::min(size.width, static_cast<int>(std::ceil(b - 0.5)));
          for (int j = j0; j < j1; ++j) cov[static_cast<std::size_t>(j)] = 1;
        }
      }
    }
    float* row = out.ptr<float>(i);
    for (int j = 0; j < size.width; ++j) row[j] = static_cast<float>(std::min(1.0, cov[static_cast<std::size_t>(j)]));
  }
  return out;
}

}  // namespace loom::draw
