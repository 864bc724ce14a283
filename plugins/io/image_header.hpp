// The pixel dimensions an image file declares in its header, read before any
// decoding, so that a small file declaring a huge image (a decompression
// bomb) is refused before anything is allocated.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace loom::io {

struct ImageSize {
  std::uint64_t width = 0, height = 0;
};

// PNG, JPEG, BMP, GIF, OpenEXR, Radiance HDR, PNM and TIFF headers; nullopt for
// other formats or a header too short to tell.
std::optional<ImageSize> declared_image_size(std::string_view bytes);

}  // namespace loom::io
