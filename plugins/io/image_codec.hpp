// Image files <-> loom::Image, through OpenCV's codecs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "loom/formats/image_header.hpp"
#include "loom/image.hpp"

namespace loom::io {

enum class Decode { linear, keep };
enum class Depth { u8, u16, f32 };

// Images whose header declares more pixels than this are refused before
// decoding (a decompression bomb).
constexpr std::uint64_t kDefaultMaxImagePixels = formats::kDefaultMaxImagePixels;

// 8- and 16-bit files hold sRGB-encoded values: `linear` decodes them and tags
// the image linear; `keep` keeps the encoded values and tags it sRGB. Float
// files (EXR, HDR) are linear already and tagged so.
// Refuses, before decoding, a file whose header declares more than
// `max_pixels` pixels (or a zero size).
Image read_image(const std::filesystem::path& path, Decode decode,
                 std::uint64_t max_pixels = kDefaultMaxImagePixels);

// Encodes by the image's tag (8/16-bit files get sRGB values, float files
// linear ones), clamps integer formats to [0, 1], writes atomically. JPEG is
// 8-bit only; EXR and HDR are float only. Throws on NaN pixels.
void write_image(const Image& image, const std::filesystem::path& path, Depth depth);

}  // namespace loom::io
