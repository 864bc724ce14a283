// Checkerboard: an RGB test image, for graphs that need no files.
#include <algorithm>

#include "loom/image.hpp"
#include "loom/plugin.hpp"

namespace {

struct Checkerboard {
  static constexpr const char* name = "Checkerboard";
  static void declare(loom::NodeSpec& s) {
    s.describe("An RGB checkerboard, tagged sRGB (the colors are taken as sRGB-encoded values).")
        .input<loom::Vec2i>("size", loom::Vec2i(512, 512), "width and height in pixels").range(1, 16384)
        .input<int>("cells", 8, "squares along the shorter side").range(1, 4096)
        .input<loom::Color>("color_a", loom::Color{{0.95, 0.95, 0.95, 1}}, "color of the corner square")
        .input<loom::Color>("color_b", loom::Color{{0.15, 0.3, 0.6, 1}}, "the other color")
        .output<loom::Image>("image", "the checkerboard");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const loom::Vec2i size = in.get<loom::Vec2i>("size");
    const int cells = in.get<int>("cells");
    const auto& a = in.get<loom::Color>("color_a").rgba;
    const auto& b = in.get<loom::Color>("color_b").rgba;
    const double cell = static_cast<double>(std::min(size.x(), size.y())) / cells;
    cv::Mat m(size.y(), size.x(), CV_32FC3);
    for (int y = 0; y < m.rows; ++y) {
      auto* row = m.ptr<cv::Vec3f>(y);
      const int cy = static_cast<int>(y / cell);
      for (int x = 0; x < m.cols; ++x) {
        const auto& c = ((static_cast<int>(x / cell) + cy) % 2 == 0) ? a : b;
        row[x] = cv::Vec3f(static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]));
      }
    }
    out.set("image", loom::Image(m, loom::Encoding::srgb));
  }
};
LOOM_NODE(Checkerboard);

}  // namespace
