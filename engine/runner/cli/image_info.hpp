// `loom info FILE...`: an image file's parts, layers and channels, and where
// it came from (the node, seed and frame Loom's writers put in its header).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace loom::runner {

// The io plugin's image library beside libloom: it links OpenImageIO, which
// `loom` itself must not (a second of dynamic linking at every start).
std::filesystem::path image_files_library();

// Prints each file's description; exit code 0, 2 for a file that cannot be
// read, 3 when lib/libloom_image_files.so cannot be loaded.
int image_info(const std::vector<std::string>& files);

}  // namespace loom::runner
