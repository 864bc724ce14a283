// Internal: whether an output path stays inside the output folder once its
// symbolic links are followed. The lexical rule (no absolute path, no ".."
// climbing out) lives in input_binding.cpp; this one reads the file system.
#pragma once

#include <filesystem>
#include <string>

namespace loom::detail {

// The path with every existing component's symbolic link followed (relative
// links against their folder, chains up to 40 deep, dangling ones too);
// components that do not exist yet are kept as written. `path` is absolute.
std::filesystem::path real_path_of(const std::filesystem::path& path);

// Throws Error when `resolved` (an absolute path lexically under `output_dir`)
// leads outside the real output folder through a symbolic link. Folders
// created later under the deepest existing component are then inside too.
// `written` is the path as the graph gave it, for the message.
void require_inside_real_output(const std::filesystem::path& resolved, const std::filesystem::path& output_dir,
                                const std::string& written);

}  // namespace loom::detail
