// Posterize: rounds each color channel to one of `levels` evenly spaced
// values, c' = round(c (L-1)) / (L-1), in the image's own encoding (so an
// sRGB image posterizes in perceptual steps). Alpha is kept.
//
// What this file shows a plugin author: declaring typed inputs with defaults
// and ranges, reading them, a clear error for bad input, a TBB loop over rows
// with progress and cancellation, and an output that keeps the input's tag.
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
        .output<loom::Image>("image", "the posterized image, with the input's encoding tag");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const loom::Image& image = in.get<loom::Image>("image");
    if (image.empty()) throw loom::Error("the image is empty");
    loom::require_finite(image, "the image");
    const float steps = static_cast<float>(in.get<int>("levels") - 1);
    const int channels = image.channels();
    const int color = (channels == 2 || channels == 4) ? channels - 1 : channels;

    cv::Mat result = image.pixels.clone();
    // Rows in chunks: the calling thread reports progress and checks for
    // cancellation between them; TBB spreads each chunk over the workers.
    constexpr int kChunk = 256;
    for (int y0 = 0; y0 < result.rows; y0 += kChunk) {
      ctx.check_cancelled();
      ctx.progress(y0, result.rows, "rows");
      const int y1 = std::min(result.rows, y0 + kChunk);
      tbb::parallel_for(tbb::blocked_range<int>(y0, y1), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
          float* p = result.ptr<float>(y);
          for (int x = 0; x < result.cols; ++x)
            for (int c = 0; c < color; ++c) p[x * channels + c] = std::round(p[x * channels + c] * steps) / steps;
        }
      });
    }
    ctx.check_cancelled();
    out.set("image", loom::Image(result, image.encoding));
  }
};
LOOM_NODE(Posterize);

}  // namespace
