// OrbitPlot: trajectories drawn around the planet, in one image (the
// assignment's "cached", "critical" and "escape" pictures side by side).
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "loom/error.hpp"
#include "loom/image.hpp"
#include "loom/plugin.hpp"
#include "loom/polylines.hpp"

namespace {

double to_srgb(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
}
cv::Scalar bgr8(const Eigen::Vector3d& rgb) {
  return cv::Scalar(255 * to_srgb(rgb[2]), 255 * to_srgb(rgb[1]), 255 * to_srgb(rgb[0]));
}

struct OrbitPlot {
  static constexpr const char* name = "OrbitPlot";

  static void declare(loom::NodeSpec& s) {
    s.describe("Draws up to four sets of trajectories (x right, y up) around a planet disc "
               "into one image, with a label for each.")
        .input<loom::Polylines>("a", "trajectories").optional()
        .input<loom::Polylines>("b", "trajectories").optional()
        .input<loom::Polylines>("c", "trajectories").optional()
        .input<loom::Polylines>("d", "trajectories").optional()
        .input<std::vector<std::string>>("labels", std::vector<std::string>{},
                                         "one per linked input, in order a, b, c, d")
        .input<loom::Vec3>("planet", loom::Vec3(0, 0, 0), "the planet's centre")
        .input<double>("planet_radius", 0.2, "drawn radius").at_least(0)
        .input<loom::Vec3>("center", loom::Vec3(0, 0, 0), "the view's centre")
        .input<double>("extent", 3.0, "half the width shown").at_least(0)
        .input<int>("width", 800, "image width and height in pixels").range(64, 8192)
        .output<loom::Image>("image", "sRGB-encoded RGB");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const int width = in.get<int>("width");
    const double extent = in.get<double>("extent");
    if (!(extent > 0)) throw loom::Error("extent must be positive");
    const loom::Vec3 center = in.get<loom::Vec3>("center");
    const double scale = width / (2 * extent);
    // 4 bits of sub-pixel precision for cv's anti-aliased lines; clamped far
    // outside the canvas, so a tiny extent or a huge radius cannot overflow int.
    auto fixed = [](double v) { return static_cast<int>(std::lround(std::clamp(v, -1e8, 1e8))); };
    auto pixel = [&](const Eigen::Vector3d& p) {
      return cv::Point(fixed(16 * (width / 2.0 + (p[0] - center[0]) * scale)),
                       fixed(16 * (width / 2.0 - (p[1] - center[1]) * scale)));
    };
    cv::Mat canvas(width, width, CV_8UC3, cv::Scalar(20, 14, 10));
    const loom::Vec3 planet = in.get<loom::Vec3>("planet");
    cv::circle(canvas, pixel(planet), fixed(16 * in.get<double>("planet_radius") * scale),
               cv::Scalar(200, 140, 70), cv::FILLED, cv::LINE_AA, 4);
    const auto labels = in.get<std::vector<std::string>>("labels");
    int drawn = 0;
    for (const char* key : {"a", "b", "c", "d"}) {
      if (!in.has(key)) continue;
      const loom::Polylines& lines = in.get<loom::Polylines>(key);
      loom::require_valid(lines, key);
      // The label takes the last vertex's colour (the ship's; body 0 is the planet).
      const Eigen::Vector3d color = lines.has_colors() && lines.vertices() > 0
                                        ? Eigen::Vector3d(lines.C.row(lines.vertices() - 1))
                                        : Eigen::Vector3d(1, 1, 1);
      for (int e = 0; e < lines.segments(); ++e) {
        const int i = lines.E(e, 0), j = lines.E(e, 1);
        const Eigen::Vector3d c = lines.has_colors() ? Eigen::Vector3d(lines.C.row(i)) : color;
        // Clip far-away segments (escaping ships) to keep coordinates in range.
        const Eigen::Vector3d p = lines.P.row(i), q = lines.P.row(j);
        if ((p - center).cwiseAbs().maxCoeff() > 100 * extent) continue;
        cv::line(canvas, pixel(p), pixel(q), bgr8(c), 2, cv::LINE_AA, 4);
      }
      if (drawn < static_cast<int>(labels.size())) {
        cv::putText(canvas, labels[static_cast<std::size_t>(drawn)], cv::Point(16, 36 + 32 * drawn),
                    cv::FONT_HERSHEY_SIMPLEX, 0.8, bgr8(color), 2, cv::LINE_AA);
      }
      ++drawn;
    }
    cv::Mat rgb;
    cv::cvtColor(canvas, rgb, cv::COLOR_BGR2RGB);
    rgb.convertTo(rgb, CV_32FC3, 1.0 / 255);
    out.set("image", loom::Image(rgb, loom::Encoding::srgb));
  }
};
LOOM_NODE(OrbitPlot);

}  // namespace
