// Procedural height fields and their tangent-space normal maps: the
// no-data input of the normal/displacement mapping demo.
#pragma once

#include <functional>

#include <opencv2/core.hpp>

namespace loom::shading {

// Running-bond bricks: `rows` courses of `columns` bricks over the image
// (every other course offset by half a brick), mortar joints `mortar` wide
// (fraction of a brick's height) at height 0, bricks at 1 with edges rounded
// over `bevel` (same unit). Tiles seamlessly. CV_32FC1 in [0, 1].
// check: a node's cancellation check, called once per row from the worker threads (may throw).
cv::Mat brick_height(int width, int height, int rows, int columns, double mortar, double bevel,
                     const std::function<void()>& check = {});

// A grid of `rows` x `columns` smooth round bumps, height 1 at their centers
// (cosine profile), 0 between them. Tiles seamlessly. CV_32FC1 in [0, 1].
cv::Mat bump_height(int width, int height, int rows, int columns, const std::function<void()>& check = {});

// Tangent-space normal map of the surface z = strength * h(u, v) over the
// unit UV square (v up, image rows go down): n ~ (-strength h_u,
// -strength h_v, 1) with central differences (wrapping around the edges
// when `wrap`, else one-sided), encoded as (n + 1) / 2. CV_32FC3.
// `strength` is the displacement scale over the world size of the UV
// square, so that the map matches displacement by that scale.
cv::Mat height_to_normal_map(const cv::Mat& height, double strength, bool wrap,
                             const std::function<void()>& check = {});

}  // namespace loom::shading
