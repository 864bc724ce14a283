// Internal: groups (format version 2) expanded into the flat Graph at load.
// A node of a group type becomes its inner nodes under "INSTANCE.INNER"; links
// to an instance's outputs and values given to its interface are rewired to
// the inner nodes, so the planner, hashing, caching and time see a flat graph.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "loom/graph.hpp"

namespace loom::detail {

using Issues = std::vector<GraphIssue>;

// graph_parse.cpp: one node's structure. `repeat`: the node may also have
// "body" and "cache_iterations".
std::optional<GraphNode> parse_node(const std::string& id, const json& node, Issues& issues, bool repeat = false);

// graph_parse.cpp: the flat nodes as a version 1 document (what Repeat hashes
// its body by; graph_to_json refuses a graph with groups).
json flat_graph_json(const Graph& g);

// Limits of the expansion, checked before anything past them is allocated
// (docs/robustness.md). Groups nest at most kMaxGroupDepth deep: expansion
// recurses once per level (10,000 levels overflowed the stack) and a chain
// of N levels makes N² characters of node paths. The expansion makes at most
// max_group_nodes() nodes in all (kMaxGroupNodes, or LOOM_MAX_GROUP_NODES):
// a group used N times is N copies of its nodes, so a 3 KB file fanning out
// 2 ways over 22 levels asked for 4 million nodes. A group file is at most
// kMaxGroupFileBytes: it holds nodes, not data.
constexpr std::size_t kMaxGroupDepth = 64;
constexpr std::size_t kMaxGroupNodes = 100000;
constexpr std::uintmax_t kMaxGroupFileBytes = 64u << 20;
std::size_t max_group_nodes();

// graph_groups.cpp: the nodes (and groups, interface) of a version 2 document.
void expand_groups(const json& doc, Graph& g, Issues& issues);

// Links naming an instance's output ("look.image") followed to the inner
// node's output; nullopt when the instance has no such output.
std::optional<Link> follow_instance_outputs(const Graph& g, Link link);

// Feeds `binding` to `target` (an inner node's input, or a nested instance's
// interface input, followed down). Throws Error when the input is already set
// and `replace` is false, or the target does not exist.
void feed_input(Graph& g, const Link& target, const InputBinding& binding, bool replace);

// The inner node inputs an interface input reaches, through nested instances.
std::vector<Link> interface_targets(const Graph& g, const GroupInput& input);

}  // namespace loom::detail

namespace loom::detail {

// group_interface.cpp: an interface input's declaration (type, default, min,
// max, choices, optional, description) as the InputSpec a C++ node would
// declare, so values given to it pass the one binding rule. Throws Error
// saying what is wrong with the declaration.
InputSpec interface_input_spec(const std::string& name, const json& declaration);

// The type of a node: a Repeat node's own (repeat.cpp) or the registry's;
// null when unknown or when a Repeat's body is invalid (validation says why).
const NodeType* node_type_of(const GraphNode& node, const Registry& registry);

}  // namespace loom::detail

namespace loom::detail {

// group_validate.cpp: against the registry, each instance's interface (the
// declarations, the values given to it, the inner inputs each feeds) and a
// group file's own interface. Issues point into the file that wrote them.
// `known_types`: node types of plugins not loaded (a group may not share a
// name with any node type, loaded or not).
void validate_groups(const Graph& g, const Registry& registry, const std::vector<std::string>& known_types,
                     Issues& issues);

}  // namespace loom::detail
