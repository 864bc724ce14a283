// SaveImage: writes an image file atomically, encoding by the image's tag.
#include "image_codec.hpp"
#include "loom/plugin.hpp"
#include "provenance.hpp"

namespace {

struct SaveImage {
  static constexpr const char* name = "SaveImage";
  static void declare(loom::NodeSpec& s) {
    s.describe("Writes PNG, JPEG, TIFF, BMP (8/16-bit, sRGB-encoded) or EXR, HDR (float, linear; EXR also "
               "half), through OpenImageIO. Converts by the image's tag, so nothing is encoded twice; writes a "
               "temporary file and renames it, so no half-written file is ever seen. A 2-channel image "
               "(gray+alpha) is written as RGBA; HDR and JPEG drop alpha. The header names the node, its seed "
               "and the frame (`loom info FILE` prints them; BMP and HDR have no place for them), and the image's "
               "colour space when it names one (ColorConvert's ACEScg: loom:colorspace). 8/16-bit files hold "
               "sRGB-encoded values: a linear image in a named space is refused for them (DisplayView or "
               "ColorConvert it first), as the sRGB curve alone would misread it.")
        .set_sink()
        .input<loom::Image>("image", "the image to write")
        .input<std::string>("path", "the file to write, relative to the output folder; {frame:04} in it becomes the "
                                    "frame number (one file per frame)")
        .output_file()
        .enum_input("depth", loom::io::Depth::u8,
                    {{loom::io::Depth::u8, "8"},
                     {loom::io::Depth::u16, "16"},
                     {loom::io::Depth::f16, "half"},
                     {loom::io::Depth::f32, "float"}},
                    "bits per channel (EXR: float unless half; HDR: float)")
        .input<bool>("tiled", false, "EXR and TIFF: store 64x64 tiles instead of scanlines");
  }
  static void run(loom::Inputs& in, loom::Outputs&, loom::Context& ctx) {
    const std::string& path = in.get<std::string>("path");
    loom::io::write_image(in.get<loom::Image>("image"), path, in.get<loom::io::Depth>("depth"),
                          loom::io::provenance(ctx), in.get<bool>("tiled"), [&ctx] { return ctx.cancelled(); });
    ctx.log("wrote " + path);
  }
};
LOOM_NODE(SaveImage);

}  // namespace
