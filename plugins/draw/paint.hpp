// Painting figures onto float images: fills by our own scan-line coverage
// (polygon_fill.hpp: sub-pixel vertices, float coverage), outlines by
// OpenCV's anti-aliased line drawing into an 8-bit coverage mask (OpenCV
// anti-aliases only 8-bit images, so it never draws on the float image
// itself), then both blended in the image's own encoding.
#pragma once

#include <opencv2/core.hpp>

#include "figures.hpp"

namespace loom::draw {

// Blends color over the image where coverage > 0: v ← v + k (c − v) with
// k = coverage · color alpha; an alpha channel (2 or 4 channels) goes to 1
// the same way. 1-2 channel images take the color's red component.
//   image     CV_32FC1..4, changed in place
//   coverage  CV_32F of the image's size, values in [0, 1]
void blend(cv::Mat& image, const cv::Mat& coverage, const Color& color);

// Paints f onto image (CV_32FC1..4): the fill first, then the outline.
// Outline widths round to whole pixels (OpenCV's thickness), at least 1.
void paint_figure(cv::Mat& image, const Figure& f);

}  // namespace loom::draw
