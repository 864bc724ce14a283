// A first layout for graphs written by hand: nodes without a "ui" position
// are placed in columns by their depth along links, stacked by height, and a
// column taller than the screen wraps into another.
#pragma once

#include <functional>
#include <string>
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
// A node's box on the canvas, in canvas units (the canvas draws it so):
// 220 wide; a header of two lines (the id, the type under it), a row of 22
// per socket and a footer for the status.
constexpr double kNodeWidth = 220, kNodeHeader = 44, kNodeRow = 22, kNodeFooter = 20;
double node_height(const NodeType* type);

CanvasPoint free_spot(const std::vector<CanvasRect>& taken, CanvasPoint wanted, double width, double height);

// A node's declaration (its "type": registered, a group, a Repeat's body),
// from its JSON; null when unknown.
using TypeLookup = std::function<const NodeType*(const json& node)>;

// Gives every node of the graph JSON `doc` that has no "ui"/"pos" one: in
// columns by depth along links, each as tall as its declaration makes it,
// moved to the nearest free spot when a placed node is in the way. No two
// boxes overlap.
void place_unplaced_nodes_in(json& doc, const TypeLookup& type_of);

}  // namespace loom::editor
