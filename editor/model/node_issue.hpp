// A validation issue placed on the canvas: which node and which input it is
// about, decoded once from its JSON pointer ("/nodes/ID/inputs/NAME/..."),
// with the pointer's escapes undone ("~1" is '/', "~0" is '~'): a node id
// may hold a '/', and its issue must land on that node.
#pragma once

#include <string>
#include <vector>

#include "loom/graph.hpp"

namespace loom::editor {

struct NodeIssue {
  std::string node;     // empty: the issue is about the graph, not one node
  std::string input;    // empty: about the node itself
  std::string pointer;  // as the engine gave it
  std::string message;
};

// The reference tokens of a JSON pointer, unescaped ("/a~1b/c" -> {"a/b", "c"}).
std::vector<std::string> pointer_tokens(const std::string& pointer);
NodeIssue locate_issue(const GraphIssue& issue);

}  // namespace loom::editor
