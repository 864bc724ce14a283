// Group files on the search path as node types to list (`loom nodes`).
#pragma once

#include <vector>

#include "loom/registry.hpp"

namespace loom::runner {

// Each group found by name (LOOM_GRAPH_PATH, then the shipped graphs/lib),
// its interface as a declaration; a group that does not load is skipped with
// a warning on stderr. The registry must hold the plugins its nodes use.
std::vector<NodeType> library_node_types(const Registry& registry);

}  // namespace loom::runner
