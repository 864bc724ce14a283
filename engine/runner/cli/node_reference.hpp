// What `loom nodes` prints: a node type in plain text, the node reference in
// Markdown (docs/nodes.md, or one type), and `--target` outputs by name.
#pragma once

#include <string>
#include <vector>

#include "loom/evaluator.hpp"
#include "loom/registry.hpp"

namespace loom::runner {

// A number as a user writes it: 2, 0.5, 1e-06 (shortest round-trip form).
std::string number_text(double v);
// "[2, 256]", "[0, ∞]": an input's bounds, or "" when it has none.
std::string range_text(const InputSpec& input);

// One line per type, or (detailed) every input with its type, default,
// range, choices and role, and every output.
std::string node_text(const NodeType& type, bool detailed);
// The Markdown reference of these types, grouped by plugin; with the page
// header when `whole_page` (docs/nodes.md).
std::string nodes_markdown(const std::vector<const NodeType*>& types, bool whole_page);

// Each requested output as "ID.OUTPUT = summary", naming every output of a
// node requested as "ID".
std::string target_lines(const Graph& graph, const Registry& registry, const EvalResult& result);

}  // namespace loom::runner
