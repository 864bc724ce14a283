// Image files <-> loom::Image, through OpenImageIO (image_files.hpp: a
// library of its own, opened at the first file).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "loom/formats/image_header.hpp"
#include "loom/image.hpp"

namespace loom::io {

enum class Decode { linear, keep };
enum class Depth { u8, u16, f16, f32 };

// Images whose header declares more pixels than this are refused before
// decoding (a decompression bomb).
constexpr std::uint64_t kDefaultMaxImagePixels = formats::kDefaultMaxImagePixels;

// Header attributes written into a file ("loom:node", ...).
using Metadata = std::vector<std::pair<std::string, std::string>>;

// 8- and 16-bit files hold sRGB-encoded values: `linear` decodes them and tags
// the image linear; `keep` keeps the encoded values and tags it sRGB. Float
// files (EXR, HDR, float TIFF) are linear already and tagged so.
// Refuses, before decoding, a file whose header declares more than
// `max_pixels` pixels (or a zero size). `layer` names a layer of a layered or
// multi-part EXR ("albedo"); "" reads the unnamed channels.
Image read_image(const std::filesystem::path& path, Decode decode, std::uint64_t max_pixels = kDefaultMaxImagePixels,
                 const std::string& layer = "");

// Encodes by the image's tag (8/16-bit files get sRGB values, float files
// linear ones), clamps integer formats to [0, 1], writes atomically. JPEG and
// BMP are 8-bit only; EXR and HDR are float only (EXR also half). Throws on
// NaN pixels. `tiled`: EXR and TIFF in 64×64 tiles. `cancelled` is asked
// between the conversions and bands of the write; true: loom::Cancelled.
void write_image(const Image& image, const std::filesystem::path& path, Depth depth, const Metadata& metadata = {},
                 bool tiled = false, const std::function<bool()>& cancelled = {});

// One layer of a layered EXR: its name and what its channels are called
// ({"R", "G", "B"}, {"X", "Y", "Z"}, {"Z"}); images of 1 channel write as
// their one name, of 3 or 4 as the first 3 or 4 names.
struct NamedImage {
  std::string name;
  Image image;
  std::vector<std::string> channels;
};

// Several images into one OpenEXR file (linear float or half), as channels
// "<name>.<channel>" of one part (Blender's and Nuke's multi-layer EXR) or,
// with `parts`, one part per image.
void write_layers(const std::vector<NamedImage>& layers, const std::filesystem::path& path, bool half, bool tiled,
                  bool parts, const Metadata& metadata);

}  // namespace loom::io
