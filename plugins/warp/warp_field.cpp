// WarpField: the displacement f(x) − x of a warp map as images, for plots,
// and the control points drawn as arrows p_i → q_i. The arrows are drawn with
// OpenCV (anti-aliased, 1/16 px positions) into an 8-bit coverage mask, then
// blended onto the float image, because OpenCV anti-aliases only 8-bit images.
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "loom/image.hpp"
#include "loom/plugin.hpp"
#include "loom/point_pairs.hpp"
#include "map_inputs.hpp"
#include "warp_image.hpp"

namespace loom::warp {
namespace {

// Hue = direction, brightness = length relative to the longest (the optical
// flow convention), as linear RGB.
cv::Mat displacement_colors(const cv::Mat& d) {
  double longest = 0;
  for (int i = 0; i < d.rows; ++i)
    for (int j = 0; j < d.cols; ++j) longest = std::max(longest, double(cv::norm(d.at<cv::Vec2f>(i, j))));
  cv::Mat hsv(d.size(), CV_32FC3);
  for (int i = 0; i < d.rows; ++i)
    for (int j = 0; j < d.cols; ++j) {
      const cv::Vec2f v = d.at<cv::Vec2f>(i, j);
      const float angle = std::atan2(v[1], v[0]) * 180.0f / float(CV_PI);
      const float len = longest > 0 ? float(cv::norm(v) / longest) : 0.0f;
      hsv.at<cv::Vec3f>(i, j) = cv::Vec3f(angle < 0 ? angle + 360 : angle, 1.0f, len);
    }
  cv::Mat rgb;
  cv::cvtColor(hsv, rgb, cv::COLOR_HSV2RGB);
  return rgb;
}

struct WarpField {
  static constexpr const char* name = "WarpField";
  static void declare(NodeSpec& s) {
    s.describe("The displacement of a warp map as images, and its control points as arrows.")
        .input<Image>("image", "background of the overlay; sets the size").optional()
        .input<Vec2i>("size", Vec2i(512, 512), "width and height when no image is given")
        .range(1, 16384);
    declare_map_inputs(s);
    s.enum_input("map", MapDirection::forward,
                 {{MapDirection::forward, "forward"}, {MapDirection::inverse, "inverse"}},
                 "forward: f(x) − x of p → q on the source; inverse: of q → p on the output")
        .input<Color>("arrow_color", Color{Eigen::Vector4d(1, 0.1, 0.1, 1)}, "color of the arrows p_i → q_i")
        .input<double>("arrow_width", 2.0, "arrow line width in pixels").range(1, 64)
        .output<Image>("displacement", "2 channels: f(x) − x in pixels (x, y), linear")
        .output<Image>("color", "hue = direction, brightness = length (RGB, linear)")
        .output<Image>("overlay", "the image (or the color plot) with arrows p_i → q_i");
  }

  static void run(Inputs& in, Outputs& out, Context& ctx) {
    const bool has_image = in.has("image");
    cv::Size size;
    if (has_image) {
      const Image& image = in.get<Image>("image");
      if (image.empty()) throw Error("image is empty: give an image or leave it unlinked and set size");
      size = image.pixels.size();
    } else {
      const Vec2i& s = in.get<Vec2i>("size");
      size = cv::Size(s.x(), s.y());
    }
    const RowMap map = fit_map(in, ctx, in.get<MapDirection>("map"));
    cv::Mat d(size, CV_32FC2);
    map_rows(map, size, 1, [&](int i, const double* fx, const double* fy) {
      cv::Vec2f* row = d.ptr<cv::Vec2f>(i);
      for (int j = 0; j < size.width; ++j)
        row[j] = cv::Vec2f(static_cast<float>(fx[j] - (j + 0.5)), static_cast<float>(fy[j] - (i + 0.5)));
    }, [&ctx](int done, int total) {
      ctx.check_cancelled();
      ctx.progress(done, total, "evaluating the map");
    });
    const cv::Mat colors = displacement_colors(d);

    // Arrows drawn over the image given, in its encoding and colour space, or over the colours.
    Image overlay_of = has_image ? in.get<Image>("image") : Image(colors, Encoding::linear);
    cv::Mat overlay = overlay_of.pixels.clone();
    cv::Mat coverage = cv::Mat::zeros(size, CV_8U);
    const PointPairs& pairs = in.get<PointPairs>("pairs");
    const int width = std::max(1, static_cast<int>(std::lround(in.get<double>("arrow_width"))));
    constexpr int kShift = 4;
    auto fixed = [](const Vec2& v) {  // pixel centers are at +0.5 here, at integers in OpenCV
      return cv::Point(static_cast<int>(std::lround((v.x() - 0.5) * (1 << kShift))),
                       static_cast<int>(std::lround((v.y() - 0.5) * (1 << kShift))));
    };
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const Vec2 &p = pairs.p[i], &q = pairs.q[i];
      if (!p.allFinite() || !q.allFinite() || p.cwiseAbs().maxCoeff() > 1e6 || q.cwiseAbs().maxCoeff() > 1e6)
        continue;
      const double length = (q - p).norm();
      if (length < 0.5)
        cv::circle(coverage, fixed(p), 3 << kShift, 255, cv::FILLED, cv::LINE_AA, kShift);  // a fixed point
      else
        cv::arrowedLine(coverage, fixed(p), fixed(q), 255, width, cv::LINE_AA, kShift,
                        std::min(0.5, (4.0 * width + 6) / length));
    }
    // Blend the arrow color by coverage; an alpha channel (2 or 4 channels) goes to 1.
    const Eigen::Vector4d color = in.get<Color>("arrow_color").rgba;
    const int C = overlay.channels();
    for (int i = 0; i < size.height; ++i) {
      float* row = overlay.ptr<float>(i);
      const unsigned char* cov = coverage.ptr<unsigned char>(i);
      for (int j = 0; j < size.width; ++j) {
        if (!cov[j]) continue;
        const float k = static_cast<float>(cov[j] / 255.0 * color[3]);
        for (int c = 0; c < C; ++c) {
          const bool alpha = (C == 2 || C == 4) && c == C - 1;
          const float target = alpha ? 1.0f : static_cast<float>(color[C <= 2 ? 0 : c]);
          row[j * C + c] += k * (target - row[j * C + c]);
        }
      }
    }
    out.set("displacement", Image(d, Encoding::linear));
    out.set("color", Image(colors, Encoding::linear));
    out.set("overlay", overlay_of.like(overlay));
  }
};
LOOM_NODE(WarpField);

}  // namespace
}  // namespace loom::warp
