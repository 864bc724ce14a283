// SaveImage: writes an image file atomically, encoding by the image's tag.
#include "image_codec.hpp"
#include "loom/plugin.hpp"

namespace {

struct SaveImage {
  static constexpr const char* name = "SaveImage";
  static void declare(loom::NodeSpec& s) {
    s.describe("Writes PNG, JPEG, TIFF, BMP (8/16-bit, sRGB-encoded) or EXR, HDR (float, linear). "
               "Converts by the image's tag, so nothing is encoded twice; writes a temporary file "
               "and renames it, so no half-written file is ever seen. A 2-channel image (gray+alpha) is "
               "written as RGBA; HDR and JPEG drop alpha.")
        .set_sink()
        .input<loom::Image>("image", "the image to write")
        .input<std::string>("path", "the file to write, relative to the output folder; {frame:04} in it becomes the frame number (one file per frame)").output_file()
        .enum_input("depth", loom::io::Depth::u8,
                    {{loom::io::Depth::u8, "8"}, {loom::io::Depth::u16, "16"}, {loom::io::Depth::f32, "float"}},
                    "bits per channel (EXR/HDR are always float)");
  }
  static void run(loom::Inputs& in, loom::Outputs&, loom::Context& ctx) {
    const std::string& path = in.get<std::string>("path");
    loom::io::write_image(in.get<loom::Image>("image"), path, in.get<loom::io::Depth>("depth"));
    ctx.log("wrote " + path);
  }
};
LOOM_NODE(SaveImage);

}  // namespace
