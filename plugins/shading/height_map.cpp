// HeightMap: procedural height fields (bricks, bumps) for normal and
// displacement mapping without data files.
#include "height_maps.hpp"
#include "loom/image.hpp"
#include "loom/plugin.hpp"

namespace {

enum class Pattern { bricks, bumps };

struct HeightMap {
  static constexpr const char* name = "HeightMap";
  static void declare(loom::NodeSpec& s) {
    s.describe("A tileable procedural height field in [0, 1]: running-bond bricks with mortar "
               "joints and rounded edges, or a grid of smooth round bumps.")
        .enum_input("pattern", Pattern::bricks, {{Pattern::bricks, "bricks"}, {Pattern::bumps, "bumps"}},
                    "what to generate")
        .input<loom::Vec2i>("size", loom::Vec2i(512, 512), "width and height in pixels")
        .input<int>("rows", 8, "brick courses, or rows of bumps").range(1, 4096)
        .input<int>("columns", 4, "bricks per course, or bumps per row").range(1, 4096)
        .input<double>("mortar", 0.12, "bricks: joint width, in brick heights").range(0, 0.9)
        .input<double>("bevel", 0.15, "bricks: width of the rounded edge, in brick heights").range(0, 1)
        .output<loom::Image>("image", "height, one channel, linear");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const auto check = [&ctx] { ctx.check_cancelled(); };
    const loom::Vec2i size = in.get<loom::Vec2i>("size");
    if (size.minCoeff() < 2 || size.maxCoeff() > 16384)
      throw loom::Error("size must be 2..16384 pixels per side");
    const int rows = in.get<int>("rows"), columns = in.get<int>("columns");
    const cv::Mat h = in.get<Pattern>("pattern") == Pattern::bumps
                          ? loom::shading::bump_height(size.x(), size.y(), rows, columns, check)
                          : loom::shading::brick_height(size.x(), size.y(), rows, columns,
                                                        in.get<double>("mortar"), in.get<double>("bevel"), check);
    out.set("image", loom::Image(h, loom::Encoding::linear));
  }
};
LOOM_NODE(HeightMap);

}  // namespace
