// A first layout for graphs written by hand: nodes without a "ui" position
// are placed in columns by their depth along links, stacked by height, and a
// column taller than the screen wraps into another.
#pragma once

#include "loom/registry.hpp"

namespace loom::editor {

// Gives every node of the graph JSON `doc` that has no "ui"/"pos" one.
void place_unplaced_nodes_in(json& doc, const Registry& registry);

}  // namespace loom::editor
