// Internal: reading one node of a graph file, and writing the flat nodes back
// (graph_parse.cpp).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "loom/graph.hpp"

namespace loom::detail {

using Issues = std::vector<GraphIssue>;

// One node's structure. `repeat`: the node may also have
// "body" and "cache_iterations".
std::optional<GraphNode> parse_node(const std::string& id, const json& node, Issues& issues, bool repeat = false);

// The flat nodes as a version 1 document (what Repeat hashes
// its body by; graph_to_json refuses a graph with groups).
json flat_graph_json(const Graph& g);

// What GroupInput::spec() keeps for the input `name`.
std::shared_ptr<ReadDeclaration> make_read_declaration(const std::string& name);

}  // namespace loom::detail
