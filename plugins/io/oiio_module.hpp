// lib/libloom_image_files.so: image files through OpenImageIO (image_files.hpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "image_files.hpp"

namespace loom::io::oiio {

ImageLayer read(const std::filesystem::path& path, const std::string& layer, std::uint64_t max_pixels);
void write(const std::vector<ImageLayer>& layers, const std::filesystem::path& path, const WriteOptions& options);
// What `loom info` prints: format, size, layers and channels, Loom's header attributes.
std::string describe(const std::filesystem::path& path);

}  // namespace loom::io::oiio
