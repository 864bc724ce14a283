// Host API. The table of node types. One Registry per engine instance; plugins add to
// it through their entry point (loom/plugin.hpp).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "loom/node.hpp"

namespace loom {

class LOOM_API Registry {
 public:
  // Adds a node type on behalf of a plugin. Throws loom::Error if the name is
  // already taken (naming both plugins).
  void add(NodeType type, const std::string& plugin);

  const NodeType* find(std::string_view name) const;
  std::vector<const NodeType*> all() const;  // sorted by name

 private:
  std::map<std::string, std::unique_ptr<NodeType>, std::less<>> types_;
};

// The JSON description of a node type: what `loom nodes --json` prints.
LOOM_API json describe_node_type(const NodeType& type);

}  // namespace loom
