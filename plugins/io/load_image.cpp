// LoadImage: an image file, or one layer of a layered EXR, as a loom::Image.
#include "image_codec.hpp"
#include "loom/input_file.hpp"
#include "loom/plugin.hpp"

namespace {

struct LoadImage {
  static constexpr const char* name = "LoadImage";
  static void declare(loom::NodeSpec& s) {
    s.describe("Reads PNG, JPEG, TIFF, BMP, EXR or HDR through OpenImageIO. 8/16-bit files are sRGB-encoded: "
               "`linear` decodes them (for rendering), `keep` keeps the encoded values (for image editing, "
               "as OpenCV and the course do). A layered or multi-part EXR gives one layer, named by `layer`; "
               "a file whose channels are not gray, gray+alpha, RGB, RGBA, XYZ or one channel is refused. The "
               "colour space a Loom file's header names (loom:colorspace, as SaveImage writes it) goes with "
               "the image, so ColorConvert and DisplayView start from it.")
        .input<std::string>("path", "the image file, relative to the graph file")
        .input_file()
        .enum_input("decode", loom::io::Decode::linear,
                    {{loom::io::Decode::linear, "linear"}, {loom::io::Decode::keep, "keep"}},
                    "decode sRGB to linear, or keep encoded values")
        .input<double>("max_pixels", static_cast<double>(loom::io::kDefaultMaxImagePixels),
                       "refuse files whose header declares more pixels than this (checked before decoding)")
        .range(1, 4e9)
        .input<std::string>("layer", std::string(),
                            "the EXR layer or part to read (\"albedo\" reads albedo.R, albedo.G, albedo.B); "
                            "empty: the unnamed channels")
        .output<loom::Image>("image", "float32 RGB(A) or gray pixels");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    loom::require_input_file(in.get<std::string>("path"), "image", ctx.graph_dir());
    out.set("image", loom::io::read_image(in.get<std::string>("path"), in.get<loom::io::Decode>("decode"),
                                          static_cast<std::uint64_t>(in.get<double>("max_pixels")),
                                          in.get<std::string>("layer")));
  }
};
LOOM_NODE(LoadImage);

}  // namespace
