// DisplayView: a scene-referred image through a view of the config's default
// display (an sRGB monitor in Loom's config), ready for an 8-bit PNG or JPEG.
#include "color_config.hpp"
#include "loom/plugin.hpp"

namespace {

using namespace loom::color;

struct DisplayView {
  static constexpr const char* name = "DisplayView";
  static void declare(loom::NodeSpec& s) {
    const Choices& c = choices();
    s.describe("Applies a display's view transform of the OpenColorIO config to an RGB(A) image: in Loom's "
               "config the sRGB display's views 'Standard' (the sRGB curve only: what SaveImage does to a "
               "linear image), 'ACES 1.0 - SDR Video' (the ACES filmic tone curve) and 'Raw'. The result is "
               "display-encoded (tagged sRGB), so SaveImage writes its values to PNG or JPEG unchanged." +
               (c.problem.empty() ? "" : " Not usable now: " + c.problem))
        .input<loom::Image>("image", "an RGB or RGBA image")
        .enum_input("from", kTagged, from_choices(),
                    "the image's colour space; 'image': the one the image names, else its tag's")
        .enum_input("view", c.default_view, c.views, "a view of the display '" + c.display + "'")
        .output<loom::Image>("image", "the image as the display shows it (display-encoded)");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const OCIO::ConstConfigRcPtr c = config();
    const auto& image = in.get<loom::Image>("image");
    const std::string from = source_space(in.get<std::string>("from"), image, c);
    const std::string& view = in.get<std::string>("view");
    try {
      const OCIO::ConstProcessorRcPtr p =
          c->getProcessor(from.c_str(), choices().display.c_str(), view.c_str(), OCIO::TRANSFORM_DIR_FORWARD);
      // What an sRGB monitor shows: the values of Loom's sRGB-encoded images.
      const loom::Image as(cv::Mat(), loom::Encoding::srgb);
      out.set("image", apply(p->getOptimizedProcessor(OCIO::OPTIMIZATION_LOSSLESS), image, as));
    } catch (const OCIO::Exception& e) {
      throw loom::Error("OpenColorIO cannot show " + from + " in view " + view + ": " + e.what());
    }
  }
};
LOOM_NODE(DisplayView);

}  // namespace
