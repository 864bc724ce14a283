#include "loom/formats/image_header.hpp"

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "loom/error.hpp"

namespace loom::formats {

namespace {

std::uint64_t be(std::string_view b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | static_cast<unsigned char>(b[at + static_cast<std::size_t>(i)]);
  return v;
}
std::uint64_t le(std::string_view b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int i = n - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + static_cast<std::size_t>(i)]);
  return v;
}

std::optional<ImageSize> jpeg(std::string_view b) {
  std::size_t i = 2;
  while (i + 9 < b.size()) {
    if (static_cast<unsigned char>(b[i]) != 0xFF) return std::nullopt;
    const auto marker = static_cast<unsigned char>(b[i + 1]);
    if (marker == 0xFF) {
      ++i;
      continue;
    }
    if (marker == 0xD8 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {
      i += 2;
      continue;
    }
    // Start of frame (any coding except DHT C4, JPG C8, DAC CC): height, width.
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC)
      return ImageSize{be(b, i + 7, 2), be(b, i + 5, 2)};
    i += 2 + be(b, i + 2, 2);
  }
  return std::nullopt;
}

// OpenEXR: attributes "name\0type\0size(int32 LE) value" until an empty name.
std::optional<ImageSize> exr(std::string_view b) {
  std::size_t i = 8;
  while (i < b.size() && b[i] != '\0') {
    const std::size_t name_end = b.find('\0', i);
    if (name_end == std::string_view::npos) return std::nullopt;
    const std::size_t type_end = b.find('\0', name_end + 1);
    if (type_end == std::string_view::npos || type_end + 5 > b.size()) return std::nullopt;
    const std::string_view name = b.substr(i, name_end - i);
    const std::uint64_t size = le(b, type_end + 1, 4);
    const std::size_t value = type_end + 5;
    if (name == "dataWindow" && size == 16 && value + 16 <= b.size()) {
      auto s32 = [&](std::size_t at) { return static_cast<std::int64_t>(static_cast<std::int32_t>(le(b, at, 4))); };
      const std::int64_t w = s32(value + 8) - s32(value) + 1, h = s32(value + 12) - s32(value + 4) + 1;
      return ImageSize{static_cast<std::uint64_t>(w > 0 ? w : 0), static_cast<std::uint64_t>(h > 0 ? h : 0)};
    }
    if (size > b.size()) return std::nullopt;
    i = value + size;
  }
  return std::nullopt;
}

// Radiance: text header, a blank line, then "-Y h +X w".
std::optional<ImageSize> hdr(std::string_view b) {
  const std::size_t blank = b.find("\n\n");
  if (blank == std::string_view::npos) return std::nullopt;
  const std::size_t end = b.find('\n', blank + 2);
  const std::string line(b.substr(blank + 2, end == std::string_view::npos ? 64 : end - blank - 2));
  char ya[3] = {}, xa[3] = {};
  unsigned long long h = 0, w = 0;
  if (std::sscanf(line.c_str(), "%2s %llu %2s %llu", ya, &h, xa, &w) != 4) return std::nullopt;
  return ImageSize{w, h};
}

// PNM: "P1".."P6", whitespace and comments, width, height.
std::optional<ImageSize> pnm(std::string_view b) {
  std::size_t i = 2;
  std::uint64_t v[2] = {0, 0};
  for (std::uint64_t& x : v) {
    while (i < b.size() && (std::isspace(static_cast<unsigned char>(b[i])) || b[i] == '#')) {
      if (b[i] == '#')
        while (i < b.size() && b[i] != '\n') ++i;
      else
        ++i;
    }
    if (i >= b.size() || !std::isdigit(static_cast<unsigned char>(b[i]))) return std::nullopt;
    while (i < b.size() && std::isdigit(static_cast<unsigned char>(b[i])) && x < (std::uint64_t(1) << 40))
      x = x * 10 + static_cast<std::uint64_t>(b[i++] - '0');
  }
  return ImageSize{v[0], v[1]};
}

// TIFF: the first IFD's ImageWidth (256) and ImageLength (257) tags.
std::optional<ImageSize> tiff(std::string_view b) {
  const bool little = b[0] == 'I';
  auto get = [&](std::size_t at, int n) { return little ? le(b, at, n) : be(b, at, n); };
  const std::uint64_t ifd = get(4, 4);
  if (ifd + 2 > b.size()) return std::nullopt;
  const std::uint64_t entries = get(ifd, 2);
  ImageSize size;
  for (std::uint64_t k = 0; k < entries; ++k) {
    const std::size_t e = ifd + 2 + 12 * k;
    if (e + 12 > b.size()) break;
    const std::uint64_t tag = get(e, 2), type = get(e + 2, 2);
    const std::uint64_t value = type == 3 ? get(e + 8, 2) : get(e + 8, 4);
    if (tag == 256) size.width = value;
    if (tag == 257) size.height = value;
  }
  if (size.width == 0 && size.height == 0) return std::nullopt;
  return size;
}

}  // namespace

std::optional<ImageSize> declared_image_size(std::string_view b) {
  if (b.size() >= 24 && b.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8))
    return ImageSize{be(b, 16, 4), be(b, 20, 4)};
  if (b.size() >= 4 && static_cast<unsigned char>(b[0]) == 0xFF && static_cast<unsigned char>(b[1]) == 0xD8) return jpeg(b);
  if (b.size() >= 26 && b.substr(0, 2) == "BM") {
    const auto h = static_cast<std::int32_t>(le(b, 22, 4));
    return ImageSize{le(b, 18, 4), static_cast<std::uint64_t>(h < 0 ? -static_cast<std::int64_t>(h) : h)};
  }
  if (b.size() >= 10 && (b.substr(0, 6) == "GIF87a" || b.substr(0, 6) == "GIF89a")) return ImageSize{le(b, 6, 2), le(b, 8, 2)};
  if (b.size() >= 8 && b.substr(0, 4) == std::string_view("\x76\x2f\x31\x01", 4)) return exr(b);
  if (b.size() >= 10 && (b.substr(0, 10) == "#?RADIANCE" || b.substr(0, 6) == "#?RGBE")) return hdr(b);
  if (b.size() >= 3 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6') return pnm(b);
  if (b.size() >= 8 && (b.substr(0, 4) == std::string_view("II*\0", 4) || b.substr(0, 4) == std::string_view("MM\0*", 4)))
    return tiff(b);
  return std::nullopt;
}

namespace {
// OpenCV's own limit, for any format whose header Loom does not read; OpenCV
// reads the variable on first use, so it is set when a plugin using these
// readers loads, before any decoding.
const bool kPixelLimitSet =
    ::setenv("OPENCV_IO_MAX_IMAGE_PIXELS", std::to_string(kDefaultMaxImagePixels).c_str(), 0) == 0;
}  // namespace

void require_declared_pixels_within(std::string_view bytes, const std::string& what, std::uint64_t max_pixels,
                                    const std::string& limit_name) {
  (void)kPixelLimitSet;
  const auto size = declared_image_size(bytes);
  if (!size) return;
  if (size->width == 0 || size->height == 0)
    throw Error("cannot decode image " + what + ": its header declares a " + std::to_string(size->width) + "×" +
                std::to_string(size->height) + " image");
  if (size->width > max_pixels / size->height)
    throw Error("cannot decode image " + what + ": its header declares " + std::to_string(size->width) + "×" +
                std::to_string(size->height) + " pixels, more than the limit of " + std::to_string(max_pixels) +
                " (" + limit_name + ")");
}

}  // namespace loom::formats
