// PolygonMask: a polygon filled into a 1-channel mask (values 0..1, linear),
// e.g. the region of a Poisson blend.
#include "loom/image.hpp"
#include "loom/plugin.hpp"
#include "polygon_fill.hpp"

namespace loom::draw {
namespace {

struct PolygonMask {
  static constexpr const char* name = "PolygonMask";
  static void declare(NodeSpec& s) {
    s.describe("Fills a polygon into a 1-channel mask (0..1) by scan lines.")
        .input<std::vector<Vec2>>("points", std::vector<Vec2>{}, "polygon vertices in pixels (closed automatically)")
        .input<Image>("image", "sets the mask size").optional()
        .input<Vec2i>("size", Vec2i(512, 512), "mask width and height when no image is given").range(1, 16384)
        .enum_input("rule", FillRule::nonzero, {{FillRule::nonzero, "nonzero"}, {FillRule::evenodd, "evenodd"}},
                    "which self-overlapping parts are inside")
        .input<bool>("antialias", true, "covered fraction per pixel (true) or pixel center inside (false)")
        .output<Image>("mask", "1 inside, 0 outside, fractions on the edge when anti-aliased");
  }

  static void run(Inputs& in, Outputs& out, Context&) {
    const std::vector<Vec2>& points = in.get<std::vector<Vec2>>("points");
    if (points.size() < 3)
      throw Error("points: a polygon needs at least 3 vertices, got " + std::to_string(points.size()));
    for (std::size_t i = 0; i < points.size(); ++i)
      if (!points[i].allFinite() || points[i].cwiseAbs().maxCoeff() > 1e7)
        throw Error("points: vertex " + std::to_string(i) + " is not a finite position within ±1e7 pixels");
    cv::Size size;
    if (in.has("image")) {
      size = in.get<Image>("image").pixels.size();
    } else {
      const Vec2i& s = in.get<Vec2i>("size");
      size = cv::Size(s.x(), s.y());
    }
    out.set("mask", Image(polygon_coverage(points, size, in.get<FillRule>("rule"), in.get<bool>("antialias")),
                          Encoding::linear));
  }
};
LOOM_NODE(PolygonMask);

}  // namespace
}  // namespace loom::draw
