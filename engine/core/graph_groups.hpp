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

// The nodes (and groups, interface) of a version 2 document.
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
