// HeightToNormalMap: a height field's tangent-space normal map, matching
// displacement mapping of the same height and scale.
#include <opencv2/imgproc.hpp>

#include "height_maps.hpp"
#include "loom/image.hpp"
#include "loom/plugin.hpp"

namespace {

struct HeightToNormalMap {
  static constexpr const char* name = "HeightToNormalMap";
  static void declare(loom::NodeSpec& s) {
    s.describe("Tangent-space normal map of the surface strength * h(u, v) over the unit UV square "
               "(central differences), encoded (n + 1) / 2: x along +u, y along +v, z out.")
        .input<loom::Image>("height", "height field (the first channel is used)")
        .input<double>("strength", 0.05,
                       "height scale over the world size of the UV square: a displacement scale of "
                       "0.1 on a 2-unit-wide plane is strength 0.05")
        .input<bool>("wrap", true, "the height tiles: differences wrap around the edges")
        .output<loom::Image>("image", "the normal map, RGB, linear-tagged [0, 1] values");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const loom::Image& height = in.get<loom::Image>("height");
    if (height.empty()) throw loom::Error("height is empty");
    loom::require_finite(height, "height");
    cv::Mat h;
    if (height.channels() == 1)
      h = height.pixels;
    else
      cv::extractChannel(height.pixels, h, 0);
    const double strength = in.get<double>("strength");
    if (!std::isfinite(strength)) throw loom::Error("strength must be finite");
    out.set("image", loom::Image(loom::shading::height_to_normal_map(h, strength, in.get<bool>("wrap"),
                                                                           [&ctx] { ctx.check_cancelled(); }),
                                 loom::Encoding::linear));
  }
};
LOOM_NODE(HeightToNormalMap);

}  // namespace
