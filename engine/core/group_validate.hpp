// Internal: the checks of groups against the registry (group_validate.cpp).
#pragma once

#include <string>
#include <vector>

#include "loom/graph.hpp"

namespace loom::detail {

// Each instance's interface (the declarations, the values given to it, the
// inner inputs each feeds) and a group file's own interface. Issues point into
// the file that wrote them. `known_types`: node types of plugins not loaded (a
// group may not share a name with any node type, loaded or not).
void validate_groups(const Graph& g, const Registry& registry, const std::vector<std::string>& known_types,
                     std::vector<GraphIssue>& issues);

}  // namespace loom::detail
