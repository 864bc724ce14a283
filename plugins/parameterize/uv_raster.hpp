// Pictures of a parameterization, so a person can judge it.
#pragma once

#include <opencv2/core.hpp>

#include <Eigen/Core>

namespace loom::parameterize {

// The UV layout: the unit square's frame and every triangle's edges, drawn
// over faces filled light grey (red where det J <= 0: flipped). v points up,
// so the image's row is (1 - v)·size. Returns size by size CV_32FC3, RGB in [0,1].
//   UV #V by 2, F #F by 3
cv::Mat draw_uv_layout(const Eigen::MatrixX2d& UV, const Eigen::MatrixX3i& F, int size);

// The mesh seen orthographically along -direction (azimuth, elevation in
// degrees), z-buffered, each pixel textured by a checkerboard of `cells`
// squares per unit of UV and shaded by |n·d|. Returns height by width CV_32FC3.
//   V #V by 3, F #F by 3, UV #V by 2
cv::Mat render_checkered(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::MatrixX2d& UV,
                         int size, int cells, double azimuth, double elevation);

}  // namespace loom::parameterize
