// MPMSplat: the particles as an image (the solver's own 2D visualization).
#include "loom/error.hpp"
#include "loom/image.hpp"
#include "loom/plugin.hpp"
#include "particle_splat.hpp"

namespace {

using namespace loom::mpm;

struct MPMSplat {
  static constexpr const char* name = "MPMSplat";

  static void declare(loom::NodeSpec& s) {
    s.describe("Draws MPM particles as anti-aliased discs of their colour into a square "
               "image of the domain (2D; 3D states are projected orthographically, far first).")
        .input<MpmState>("state", "the particles")
        .input<int>("width", 512, "image width and height in pixels").range(8, 16384)
        .input<double>("size", 1.0, "the domain edge length (as in MPMStep)").at_least(0)
        .input<double>("radius", 1.0, "disc radius in pixels").range(0.1, 64)
        .input<loom::Color>("background", loom::Color{Eigen::Vector4d(0.02, 0.02, 0.03, 1)},
                            "linear RGB")
        .enum_input("view", View::front, {{View::front, "front"}, {View::top, "top"}, {View::side, "side"}},
                    "3D only: look along −z (front), −y (top) or −x (side)")
        .output<loom::Image>("image", "linear RGB");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    SplatOptions o;
    o.width = in.get<int>("width");
    o.size = in.get<double>("size");
    if (!(o.size > 0)) throw loom::Error("size must be positive");
    o.radius_px = in.get<double>("radius");
    o.background = in.get<loom::Color>("background").rgba.head<3>().cast<float>();
    o.view = in.get<View>("view");
    out.set("image", loom::Image(splat(in.get<MpmState>("state"), o), loom::Encoding::linear));
  }
};
LOOM_NODE(MPMSplat);

}  // namespace
