// Scan-line polygon filling into a coverage image, with the even-odd or the
// nonzero winding rule, optionally anti-aliased. Our own rather than
// cv::fillPoly because OpenCV anti-aliases only 8-bit images, positions
// vertices at 1/2^shift px, and has no choice of rule; here vertices are
// doubles and coverage is float.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace loom::draw {

enum class FillRule { nonzero, evenodd };

// Coverage of each pixel by the closed polygon (the last point joins the
// first), pixel centers at (j + 0.5, i + 0.5).
//   polygon    #n vertices in pixels, n >= 3 (fewer cover nothing)
//   antialias  false: 1 where the pixel center is inside, else 0.
//              true: the covered fraction of the pixel, exact along each of
//              16 sub-scanlines per row (so to 1/32 px vertically).
// Returns CV_32F of `size`, values in [0, 1].
cv::Mat polygon_coverage(const std::vector<Eigen::Vector2d>& polygon, cv::Size size, FillRule rule,
                         bool antialias);

}  // namespace loom::draw
