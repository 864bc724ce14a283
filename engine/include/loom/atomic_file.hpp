// Plugin author API. Writing output files so that a reader never sees half of one: write a
// staging file in the same folder (loom/temporary_file.hpp), check every
// write, the flush to disk and the close, then rename it over the target.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "loom/export.hpp"

namespace loom {

// Creates missing parent folders. Throws loom::Error naming the path on failure
// and leaves no temporary file behind.
LOOM_API void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

// Several files that belong together (an .obj and its .mtl): every one is
// staged and checked before any is renamed into place, so a failing write
// (a full disk) changes none of them; should a rename fail, the files already
// renamed by this call are removed.
LOOM_API void write_files_atomic(const std::vector<std::pair<std::filesystem::path, std::string>>& files);

}  // namespace loom
