// The picture of a parameterization in UV space, so a person can judge it.
// (Renders of the mesh itself go through the shading plugin's Render node.)
#pragma once

#include <opencv2/core.hpp>

#include <Eigen/Core>

namespace loom::parameterize {

// The UV layout: the unit square's frame and every triangle's edges, drawn
// over faces filled light grey (red where det J <= 0: flipped). v points up,
// so the image's row is (1 - v)·size. Returns size by size CV_32FC3, RGB in [0,1].
//   UV #V by 2, F #F by 3
cv::Mat draw_uv_layout(const Eigen::MatrixX2d& UV, const Eigen::MatrixX3i& F, int size);

}  // namespace loom::parameterize
