// Checkerboard: an RGB test image, for graphs that need no files.
#include "generators.hpp"
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
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const cv::Mat m = loom::generate::checkerboard(in.get<loom::Vec2i>("size"), in.get<int>("cells"),
                                                   in.get<loom::Color>("color_a"), in.get<loom::Color>("color_b"),
                                                   [&ctx] { ctx.check_cancelled(); });
    out.set("image", loom::Image(m, loom::Encoding::srgb));
  }
};
LOOM_NODE(Checkerboard);

}  // namespace
