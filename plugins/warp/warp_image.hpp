// Moving pixels through a plane map, in pixel coordinates: pixel (row i,
// column j) has its center at (j + 0.5, i + 0.5), origin top-left, y down.
//
//   inverse_warp  out(x) = src(f(x)) for every output pixel x, sampled
//                 bilinearly: f maps output to source, no pixel is left out.
//   forward_warp  out(round(f(x))) = src(x) for every source pixel x (the
//                 assignment's splatting): f maps source to output, and
//                 magnified regions get cracks no source pixel lands on.
//   fill_cracks   fills those cracks from their written neighbours.
#pragma once

#include <functional>

#include <opencv2/core.hpp>

namespace loom::warp {

// A plane map along rows: fx[j], fy[j] = f(x[j], y) for j < n. Called from
// several threads at once.
using RowMap = std::function<void(double y, const double* x, int n, double* fx, double* fy)>;
// Called from the calling thread between blocks of rows with (rows done,
// rows total); may throw (loom::Cancelled) to stop.
using RowProgress = std::function<void(int, int)>;

// Calls body(i, fx, fy) with f at the centers of row i of a size.width ×
// size.height grid, rows in parallel (TBB). step = 1 evaluates f at every
// pixel; step = s > 1 evaluates it at every s-th pixel center (and the last
// one) in both directions and interpolates bilinearly between.
void map_rows(const RowMap& f, cv::Size size, int step,
              const std::function<void(int, const double*, const double*)>& body,
              const RowProgress& progress);

enum class Outside { background, replicate };

// source: CV_32FC1..4; to_source: output → source positions. Positions outside
// the source's [0, w] × [0, h] take `background` (Outside::background) or the
// nearest edge pixel (Outside::replicate). Never NaN for a finite source.
// Returns an image of `size` with the source's type.
cv::Mat inverse_warp(const cv::Mat& source, const RowMap& to_source, cv::Size size, int step,
                     Outside outside, const cv::Scalar& background, const RowProgress& progress);

struct Splat {
  cv::Mat image;         // the output, background where nothing landed
  cv::Mat written;       // CV_8U, 255 where a source pixel landed
  double max_stretch = 0;  // largest distance between images of neighbouring pixels
};

// source: CV_32FC1..4; to_target: source → output positions. Each source
// pixel is written to the output pixel nearest to its image; when several
// land on one pixel the last in row-major order wins (as in the assignment).
Splat forward_warp(const cv::Mat& source, const RowMap& to_target, cv::Size size, int step,
                   const cv::Scalar& background, const RowProgress& progress);

// Fills the cracks of a forward warp: unwritten pixels inside the
// morphological closing of `written` by a disk of the given radius (so the
// background around the warped image stays), each set to the mean of its
// written or already filled 8-neighbours, sweeping inwards (at most 2·radius
// sweeps). Filled pixels are marked in `written`; returns how many.
int fill_cracks(cv::Mat& image, cv::Mat& written, int radius);

}  // namespace loom::warp
