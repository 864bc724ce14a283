// Plugin author API. Image: float32 pixels, 1 to 4 channels (gray, gray+alpha, RGB, RGBA, in that
// order: RGB, not OpenCV's BGR), row-major, origin top-left, y down. Tagged
// with its encoding so nothing is converted twice: LoadImage decodes sRGB to
// linear by default or keeps the encoded values (image editing works on those,
// as OpenCV and the course do); SaveImage encodes by the tag. An image may also
// name the OpenColorIO colour space its values are in (ColorConvert's target,
// an EXR's header); unnamed, it is in the space its encoding stands for.
//
// Lives in libloom_types (OpenCV core) so graphs without images never load it.
#pragma once

#include <string>
#include <utility>

#include <opencv2/core.hpp>

#include "loom/value.hpp"

namespace loom {

enum class Encoding { linear, srgb };

struct Image {
  cv::Mat pixels;  // CV_32FC1..CV_32FC4
  Encoding encoding = Encoding::linear;
  // The colour space by its name in the OpenColorIO config, or empty for the
  // one the encoding stands for: the config's scene_linear role for linear
  // images, its color_picking role for sRGB-encoded ones (lin_rec709 and srgb
  // in Loom's config). Only the color plugin names spaces; it leaves this
  // empty for those two, so one image has one description.
  std::string space;

  Image() = default;
  Image(cv::Mat m, Encoding e, std::string s = {}) : pixels(std::move(m)), encoding(e), space(std::move(s)) {}

  // Other pixels with this image's meaning (encoding and colour space): what
  // a node that warps, blends or draws on an image outputs.
  Image like(cv::Mat m) const { return Image(std::move(m), encoding, space); }

  int width() const { return pixels.cols; }
  int height() const { return pixels.rows; }
  int channels() const { return pixels.channels(); }
  bool empty() const { return pixels.empty(); }
};

// sRGB transfer functions (IEC 61966-2-1), per value; alpha is never encoded.
LOOM_API float srgb_to_linear(float encoded);
LOOM_API float linear_to_srgb(float linear);
// Converts color channels (not alpha) of a copy to the requested encoding.
// An image in a named colour space (ACEScg, ...) keeps its encoding or is
// refused: the sRGB curve alone would not take it to sRGB, ColorConvert does.
LOOM_API Image with_encoding(const Image& image, Encoding target);
// "linear", "sRGB", or "linear ACEScg": what an error or a summary says.
LOOM_API std::string describe_space(const Image& image);

// Throws loom::Error if any pixel is NaN or infinite ("what" names the image).
LOOM_API void require_finite(const Image& image, const char* what);

template <>
struct TypeTraits<Image> {
  static constexpr const char* name = "Image";
  static constexpr const char* description =
      "float32 pixels, 1-4 channels (RGB order), tagged linear or sRGB-encoded, with its colour space's name "
      "when not the encoding's own";
  LOOM_API static std::string summary(const Image& image);
  static constexpr int version = 2;  // 2: the colour space's name
  LOOM_API static void write(const Image& v, ByteWriter& w);
  LOOM_API static Image read(ByteReader& r);
  LOOM_API static std::size_t bytes(const Image& v);
  LOOM_API static void check(const Image& v);
};

}  // namespace loom
