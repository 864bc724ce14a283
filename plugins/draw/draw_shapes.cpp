// DrawShapes: the MiniDraw assignment as a node. Figures are plain JSON (see
// figures.hpp) so that the editor can later draw them interactively.
#include "figures.hpp"
#include "loom/image.hpp"
#include "loom/plugin.hpp"
#include "paint.hpp"

namespace loom::draw {
namespace {

struct DrawShapes {
  static constexpr const char* name = "DrawShapes";
  static void declare(NodeSpec& s) {
    s.describe("Draws lines, rectangles, rounded rectangles, ellipses, polygons, freehand strokes and arrows, "
               "anti-aliased, onto an image or a blank canvas.")
        .input<Image>("image", "the image to draw on (else a blank canvas)").optional()
        .input<Vec2i>("size", Vec2i(512, 512), "canvas width and height when no image is given").range(1, 16384)
        .input<Color>("background", Color{Eigen::Vector4d(1, 1, 1, 1)}, "canvas color (sRGB-encoded RGB canvas)")
        .input<json>("figures", json::array(),
                     "list of figures: {\"type\": \"line\"|\"arrow\"|\"rectangle\"|\"rounded_rectangle\"|\"ellipse\"|"
                     "\"polygon\"|\"freehand\", geometry keys, \"stroke\", \"width\", \"fill\"}")
        .output<Image>("image", "the drawing, in the input's encoding (colors are taken in that encoding)");
  }

  static void run(Inputs& in, Outputs& out, Context& ctx) {
    const std::vector<Figure> figures = parse_figures(in.get<json>("figures"));
    Image canvas;
    if (in.has("image")) {
      const Image& image = in.get<Image>("image");
      if (image.empty()) throw Error("image is empty: link a non-empty image, or unlink it for a blank canvas");
      canvas = image.like(image.pixels.clone());
    } else {
      const Vec2i& size = in.get<Vec2i>("size");
      const Eigen::Vector4d& bg = in.get<Color>("background").rgba;
      canvas = Image(cv::Mat(size.y(), size.x(), CV_32FC3, cv::Scalar(bg[0], bg[1], bg[2])), Encoding::srgb);
    }
    for (std::size_t i = 0; i < figures.size(); ++i) {
      paint_figure(canvas.pixels, figures[i]);
      ctx.progress(double(i + 1), double(figures.size()), "drawing figures");
      ctx.check_cancelled();
    }
    out.set("image", std::move(canvas));
  }
};
LOOM_NODE(DrawShapes);

}  // namespace
}  // namespace loom::draw
