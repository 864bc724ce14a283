#include "loom/image.hpp"

#include <cmath>
#include <sstream>

#include <opencv2/core.hpp>

namespace loom {

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float c) {
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

Image with_encoding(const Image& image, Encoding target) {
  if (image.encoding == target) return image;
  Image out(image.pixels.clone(), target);
  const int ch = out.channels();
  const int color = (ch == 2 || ch == 4) ? ch - 1 : ch;  // alpha is never encoded
  auto convert = target == Encoding::linear ? srgb_to_linear : linear_to_srgb;
  for (int y = 0; y < out.height(); ++y) {
    float* row = out.pixels.ptr<float>(y);
    for (int x = 0; x < out.width(); ++x)
      for (int c = 0; c < color; ++c) row[x * ch + c] = convert(row[x * ch + c]);
  }
  return out;
}

void require_finite(const Image& image, const char* what) {
  if (!cv::checkRange(image.pixels, true, nullptr, -3.0e38, 3.0e38))
    throw Error(std::string(what) + " has NaN or infinite pixels");
}

std::string TypeTraits<Image>::summary(const Image& image) {
  std::ostringstream s;
  s << "Image " << image.width() << "x" << image.height() << "x" << image.channels() << " "
    << (image.encoding == Encoding::srgb ? "sRGB" : "linear");
  return s.str();
}

}  // namespace loom
