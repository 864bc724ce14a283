// ImageWarp: moves an image so that each p_i lands on q_i (ImageWarping
// assignment). Which map is fitted depends on the mode:
//   inverse  fits f⁻¹ on the swapped pairs q_i → p_i and samples the source
//            at f⁻¹(x) for every output pixel x: no holes.
//   forward  fits f on p_i → q_i and splats every source pixel to f(x), as
//            the assignment does; magnified regions crack ("white lines")
//            unless fill_holes fills them.
#include <algorithm>
#include <cmath>

#include "loom/image.hpp"
#include "loom/plugin.hpp"
#include "map_inputs.hpp"
#include "warp_image.hpp"

namespace loom::warp {
namespace {

struct ImageWarp {
  static constexpr const char* name = "ImageWarp";
  static void declare(NodeSpec& s) {
    s.describe("Warps an image so that control points p_i move to q_i, by IDW or RBF.")
        .input<Image>("image", "the image to warp");
    declare_map_inputs(s);
    s.enum_input("mode", MapDirection::inverse,
                 {{MapDirection::inverse, "inverse"}, {MapDirection::forward, "forward"}},
                 "inverse: sample the source per output pixel; forward: splat source pixels")
        .input<bool>("fill_holes", true, "forward: fill the cracks no source pixel lands on")
        .enum_input("outside", Outside::background,
                    {{Outside::background, "background"}, {Outside::replicate, "replicate"}},
                    "inverse: what pixels mapped outside the source show")
        .input<Color>("background", Color{Eigen::Vector4d(1, 1, 1, 1)},
                      "color where nothing lands, in the image's encoding")
        .input<int>("map_step", 1, "evaluate the map at every n-th pixel and interpolate between (1: exact)")
        .range(1, 64)
        .output<Image>("image", "the warped image, same size and encoding")
        .output<Image>("holes", "forward: 1 where no source pixel landed nor a crack fill reached (also the background around the result); inverse: all 0");
  }

  static void run(Inputs& in, Outputs& out, Context& ctx) {
    const Image& image = in.get<Image>("image");
    if (image.empty()) throw Error("image is empty: nothing to warp");
    require_finite(image, "image");
    const MapDirection mode = in.get<MapDirection>("mode");
    const RowMap map = fit_map(in, ctx, mode);
    const Eigen::Vector4d bg = in.get<Color>("background").rgba;
    const cv::Scalar background(bg[0], bg[1], bg[2], bg[3]);
    const int step = in.get<int>("map_step");
    auto progress = [&ctx](int done, int total) {
      ctx.check_cancelled();
      ctx.progress(done, total, "warping rows");
    };
    cv::Mat holes;
    cv::Mat warped;
    if (mode == MapDirection::inverse) {
      warped = inverse_warp(image.pixels, map, image.pixels.size(), step, in.get<Outside>("outside"), background,
                            progress);
      holes = cv::Mat::zeros(image.pixels.size(), CV_32F);
    } else {
      Splat splat = forward_warp(image.pixels, map, image.pixels.size(), step, background, progress);
      if (in.get<bool>("fill_holes")) {
        const int radius = std::clamp(static_cast<int>(std::ceil(splat.max_stretch)), 1, 16);
        fill_cracks(splat.image, splat.written, radius);
      }
      warped = splat.image;
      cv::Mat unwritten = ~splat.written;
      unwritten.convertTo(holes, CV_32F, 1.0 / 255);
    }
    out.set("image", image.like(warped));
    out.set("holes", Image(holes, Encoding::linear));
  }
};
LOOM_NODE(ImageWarp);

}  // namespace
}  // namespace loom::warp
