// The pixel dimensions an image file declares in its header, read before any
// decoding, so that a small file declaring a huge image (a decompression
// bomb) is refused before anything is allocated.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace loom::formats {

struct ImageSize {
  std::uint64_t width = 0, height = 0;
};

// PNG, JPEG, BMP, GIF, OpenEXR, Radiance HDR, PNM and TIFF headers; nullopt for
// other formats or a header too short to tell.
std::optional<ImageSize> declared_image_size(std::string_view bytes);

// Images whose header declares more pixels than this are refused before
// decoding (a decompression bomb): 2^28, e.g. 16384 × 16384. OpenCV's own
// limit (OPENCV_IO_MAX_IMAGE_PIXELS) is set to it for formats Loom's header
// reader does not know.
constexpr std::uint64_t kDefaultMaxImagePixels = std::uint64_t(1) << 28;

// Throws loom::Error naming `what` when the header in `bytes` (the file's
// start) declares a zero size or more than `max_pixels` pixels; `limit_name`
// says where the limit comes from ("LoadImage's max_pixels").
void require_declared_pixels_within(std::string_view bytes, const std::string& what, std::uint64_t max_pixels,
                                    const std::string& limit_name);

}  // namespace loom::formats
