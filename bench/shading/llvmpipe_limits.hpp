// llvmpipe's limits on this machine, measured through the same OSMesa context
// Loom's Render node uses, and the Render node's target frame beside them
// (alternating run by run): raw fill rate, depth-only fill, the 5x5 PCF's
// gathers, triangle setup; the frame's time at those rates and the fraction
// of the limit (limit time / Render's time). Writes shading_limits.csv,
// shading_fill_rate.csv and its plot.
#pragma once

#include <functional>

#include "rasterizer.hpp"

namespace loom::shading {

// The Render frame to compare with, and the work it does per frame.
struct RenderFrame {
  std::function<void(RenderTimings&)> run;  // one steady frame, per-pass timings filled in
  int width = 1920, height = 1080, samples = 4, shadow_resolution = 2048, pcf_size = 5;
  long long triangles = 100000;
};

void llvmpipe_limits(bool quick, const RenderFrame& render);

}  // namespace loom::shading
