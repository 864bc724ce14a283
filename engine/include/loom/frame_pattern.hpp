// Plugin author API. Frame numbers in output paths: "frames/cloth_{frame:04}.png" at frame 7 is
// "frames/cloth_0007.png". {frame} is the plain number, {frame:N} pads it with
// zeros to N digits (also written {frame:0N}). The engine expands every
// output-file input this way before a node runs, so each sink writes one file
// per frame; any other braces are left as they are.
#pragma once

#include <string>

#include "loom/export.hpp"

namespace loom {

LOOM_API std::string expand_frame_pattern(const std::string& path, int frame);
LOOM_API bool has_frame_pattern(const std::string& path);

}  // namespace loom
