// ColorConvert: an image from one colour space of the OpenColorIO config to
// another (OCIO's CPU processor, lossless optimization: the built-in
// transforms' exact matrices and curves, no fast approximations).
#include "color_config.hpp"
#include "loom/plugin.hpp"

namespace {

using namespace loom::color;

struct ColorConvert {
  static constexpr const char* name = "ColorConvert";
  static void declare(loom::NodeSpec& s) {
    const Choices& c = choices();
    s.describe("Converts an RGB(A) image between two colour spaces of the OpenColorIO config: $OCIO when set, "
               "else Loom's (share/ocio/loom.ocio: lin_rec709, srgb, ACEScg, ACES2065-1, ACEScct...; "
               "docs/color.md). Loom's linear images are lin_rec709, its sRGB-encoded ones srgb, unless they "
               "name another space. Alpha passes through. The result is tagged linear (scene- or "
               "display-linear spaces) or sRGB-encoded (display-encoded spaces) and names its space when it "
               "is another than those two (ACEScg): nodes after it start from that space, SaveImage writes "
               "it into the file's header and will not put it through the sRGB curve alone. Other spaces "
               "(log, data) are refused." +
               (c.problem.empty() ? "" : " Not usable now: " + c.problem))
        .input<loom::Image>("image", "an RGB or RGBA image")
        .enum_input("from", kTagged, from_choices(),
                    "the image's colour space; 'image': the one the image names, else its tag's")
        .enum_input("to", c.linear_space, c.spaces, "the colour space to convert to")
        .output<loom::Image>("image", "the converted image");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const OCIO::ConstConfigRcPtr c = config();
    const auto& image = in.get<loom::Image>("image");
    const std::string from = source_space(in.get<std::string>("from"), image, c);
    const std::string& to = in.get<std::string>("to");
    const loom::Image as = described_as(to, c);
    try {
      const OCIO::ConstProcessorRcPtr p = c->getProcessor(from.c_str(), to.c_str());
      out.set("image", apply(p->getOptimizedProcessor(OCIO::OPTIMIZATION_LOSSLESS), image, as));
    } catch (const OCIO::Exception& e) {
      throw loom::Error("OpenColorIO cannot convert " + from + " to " + to + ": " + e.what());
    }
  }
};
LOOM_NODE(ColorConvert);

}  // namespace
