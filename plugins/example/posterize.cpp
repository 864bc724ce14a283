// Posterize: rounds each color channel to one of `levels` evenly spaced
// values, c' = round(c (L-1)) / (L-1), in the image's own encoding (so an
// sRGB image posterizes in perceptual steps). Alpha is kept.
//
// What this file shows a plugin author: declaring typed inputs with defaults
// and ranges, reading them, a clear error for bad input, a TBB loop over rows
// with progress and cancellation, an output that keeps the input's tag, and a
// per-pixel node that lets the engine split its image (set_pixel_independent).
// Progress and cancellation are checked on the calling thread between bands
// of rows, never inside the parallel_for body (the host is not called from
// TBB workers).
#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "loom/image.hpp"
#include "loom/plugin.hpp"

namespace {

struct Posterize {
  static constexpr const char* name = "Posterize";

  static void declare(loom::NodeSpec& s) {
    s.describe("Rounds each color channel to one of `levels` values (alpha is kept).")
        .input<loom::Image>("image", "the image to posterize")
        .input<int>("levels", 4, "values per channel").range(2, 256)
        .output<loom::Image>("image", "the posterized image, with the input's encoding tag")
        .set_pixel_independent();
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const loom::Image& image = in.get<loom::Image>("image");
    if (image.empty()) throw loom::Error("the image is empty");
    loom::require_finite(image, "the image");
    const float steps = static_cast<float>(in.get<int>("levels") - 1);
    const int channels = image.channels();
    const int color = (channels == 2 || channels == 4) ? channels - 1 : channels;

    // Pixels are float32, channels interleaved in RGB(A) order, values in the
    // image's encoding: posterizing never needs to convert.
    cv::Mat result = image.pixels.clone();
    // Split over processes, only this part's tiles (the engine gathers the rest).
    const loom::PixelRegion region = ctx.region();
    constexpr int kBand = 64;  // rows between progress reports
    for (int band = 0; band < result.rows; band += kBand) {
      ctx.check_cancelled();
      const int end = std::min(band + kBand, result.rows);
      tbb::parallel_for(tbb::blocked_range<int>(band, end), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
          float* p = result.ptr<float>(y);
          for (int x = 0; x < result.cols; ++x)
            if (region.contains(x, y, result.cols))
              for (int c = 0; c < color; ++c) p[x * channels + c] = std::round(p[x * channels + c] * steps) / steps;
        }
      });
      ctx.progress(end, result.rows, "rows");
    }
    out.set("image", image.like(result));
  }
};
LOOM_NODE(Posterize);

}  // namespace
