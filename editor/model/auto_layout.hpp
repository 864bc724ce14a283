// A first layout for graphs written by hand: nodes without a "ui" position
// are placed in columns by their depth along links, stacked by height, and a
// column taller than the screen wraps into another.
#pragma once

#include <vector>

#include "loom/registry.hpp"
#include "model/graph_document.hpp"

namespace loom::editor {

struct CanvasRect {
  double x = 0, y = 0, width = 0, height = 0;  // canvas units, y down
};

// Where a new node of this size goes: the free spot nearest to `wanted` (its
// top-left corner), keeping a margin from every taken rectangle; `wanted`
// itself when nothing is free within reach.
// A node's box on the canvas, in canvas units: 220 wide, a header and
// footer of 48 and 22 per socket row (the canvas draws it so).
constexpr double kNodeWidth = 220;
double node_height(const NodeType* type);

CanvasPoint free_spot(const std::vector<CanvasRect>& taken, CanvasPoint wanted, double width, double height);

// Gives every node of the graph JSON `doc` that has no "ui"/"pos" one.
void place_unplaced_nodes_in(json& doc, const Registry& registry);

}  // namespace loom::editor
