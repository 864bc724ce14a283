// Internal: the Repeat node, which runs a body group N times, threading the
// body outputs that match a body input (same name and type) from one iteration
// to the next. See docs/graph-format.md, "Repeat", and docs/architecture.md.
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include "loom/graph.hpp"

namespace loom {

struct RepeatBody {
  std::string body_type;             // as written in "body"
  std::shared_ptr<const Graph> body;  // flat, with its interface
  bool cache_iterations = false;
  // Built on first use from the body's interface and the registry (types are
  // known once plugins are loaded).
  mutable std::mutex mutex;
  mutable std::unique_ptr<NodeType> type;
};

}  // namespace loom

namespace loom::detail {

std::shared_ptr<const RepeatBody> make_repeat_body(std::string body_type, std::shared_ptr<const Graph> body,
                                                   bool cache_iterations);

// The Repeat node's declaration: "count" (Int >= 0) and the body's inputs;
// the body's outputs. Throws Error for a body whose interface is invalid.
const NodeType& repeat_node_type(const RepeatBody& repeat, const Registry& registry);

// The type of a graph node: a Repeat node's own or the registry's; null when
// unknown or when a Repeat's body is invalid (validation says why).
const NodeType* node_type_of(const GraphNode& node, const Registry& registry);

}  // namespace loom::detail
