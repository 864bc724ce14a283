// Writing output files so that a reader never sees half of one: write a
// temporary file in the same folder, flush it, then rename it over the target.
#pragma once

#include <filesystem>
#include <string_view>

#include "loom/export.hpp"

namespace loom {

// Creates missing parent folders. Throws loom::Error naming the path on failure
// and leaves no temporary file behind.
LOOM_API void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

}  // namespace loom
