#include "paint.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace loom::draw {

namespace {

constexpr int kShift = 4;  // OpenCV positions at 1/16 px

// Loom puts pixel centers at +0.5, OpenCV at integers; o is the ROI origin.
cv::Point fixed(const Eigen::Vector2d& p, const cv::Point& o) {
  return cv::Point(static_cast<int>(std::lround((p.x() - 0.5 - o.x) * (1 << kShift))),
                   static_cast<int>(std::lround((p.y() - 0.5 - o.y) * (1 << kShift))));
}

cv::Mat stroke_coverage(const Figure& f, const std::vector<Eigen::Vector2d>& outline, const cv::Rect& roi) {
  cv::Mat mask = cv::Mat::zeros(roi.size(), CV_8U);
  const int thickness = std::max(1, static_cast<int>(std::lround(f.width)));
  const cv::Point o = roi.tl();
  std::vector<cv::Point> pts;
  for (const auto& p : outline) pts.push_back(fixed(p, o));
  if (f.type == FigureType::arrow) {
    const double length = (f.points[1] - f.points[0]).norm();
    if (length > 0)
      cv::arrowedLine(mask, pts[0], pts[1], 255, thickness, cv::LINE_AA, kShift, std::min(1.0, f.head / length));
  } else if (f.type == FigureType::line) {
    cv::line(mask, pts[0], pts[1], 255, thickness, cv::LINE_AA, kShift);
  } else {
    cv::polylines(mask, std::vector<std::vector<cv::Point>>{pts}, is_closed(f.type), 255, thickness, cv::LINE_AA,
                  kShift);
  }
  cv::Mat coverage;
  mask.convertTo(coverage, CV_32F, 1.0 / 255);
  return coverage;
}

}  // namespace

void blend(cv::Mat& image, const cv::Mat& coverage, const Color& color) {
  const int C = image.channels();
  const bool has_alpha = C == 2 || C == 4;
  for (int i = 0; i < image.rows; ++i) {
    float* row = image.ptr<float>(i);
    const float* cov = coverage.ptr<float>(i);
    for (int j = 0; j < image.cols; ++j) {
      if (cov[j] <= 0) continue;
      const float k = static_cast<float>(cov[j] * color.rgba[3]);
      for (int c = 0; c < C; ++c) {
        const bool alpha = has_alpha && c == C - 1;
        const float target = alpha ? 1.0f : static_cast<float>(color.rgba[C <= 2 ? 0 : c]);
        row[j * C + c] += k * (target - row[j * C + c]);
      }
    }
  }
}

void paint_figure(cv::Mat& image, const Figure& f) {
  const std::vector<Eigen::Vector2d> outline = figure_outline(f);
  if (outline.empty()) return;
  // Only the pixels the figure can touch: its bounding box grown by the outline width.
  Eigen::Vector2d lo = outline[0], hi = outline[0];
  for (const auto& p : outline) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double grow = f.width / 2 + (f.type == FigureType::arrow ? f.head : 0) + 2;
  const cv::Rect box(cv::Point(static_cast<int>(std::floor(std::max(lo.x() - grow, -1.0))),
                               static_cast<int>(std::floor(std::max(lo.y() - grow, -1.0)))),
                     cv::Point(static_cast<int>(std::ceil(std::min(hi.x() + grow, image.cols + 1.0))),
                               static_cast<int>(std::ceil(std::min(hi.y() + grow, image.rows + 1.0)))));
  const cv::Rect roi = box & cv::Rect(0, 0, image.cols, image.rows);
  if (roi.empty()) return;
  cv::Mat target = image(roi);
  if (f.fill && is_closed(f.type)) {
    std::vector<Eigen::Vector2d> shifted = outline;
    for (auto& p : shifted) p -= Eigen::Vector2d(roi.x, roi.y);
    blend(target, polygon_coverage(shifted, roi.size(), f.fill_rule, true), *f.fill);
  }
  if (f.width > 0) blend(target, stroke_coverage(f, outline, roi), f.stroke);
}

}  // namespace loom::draw
