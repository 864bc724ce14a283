// Host API. The one reader of Loom's search path variables (LOOM_PLUGIN_PATH,
// LOOM_GRAPH_PATH).
#pragma once

#include <filesystem>
#include <vector>

#include "loom/export.hpp"

namespace loom {

// The folders a ':'-separated search path variable lists, in order. Empty
// entries are skipped. A relative entry is ignored with a warning on stderr
// naming the variable: it would make whatever folder loom runs in a source of
// plugins or group files. An unset variable lists nothing.
LOOM_API std::vector<std::filesystem::path> search_path_from_env(const char* variable);

}  // namespace loom
