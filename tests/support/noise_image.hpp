// A float image of uniform noise in [low, high): test data whose every value
// differs, so a swapped channel or layer cannot pass unseen.
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

#include "loom/image.hpp"

namespace loom::test {

inline Image noise_image(int rows, int cols, int channels, float low, float high, int seed) {
  cv::Mat m(rows, cols, CV_MAKETYPE(CV_32F, channels));
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  rng.fill(m, cv::RNG::UNIFORM, low, high);
  return Image(m, Encoding::linear);
}

}  // namespace loom::test
