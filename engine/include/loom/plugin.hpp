// Plugin author API. Plugin entry points. A plugin is one shared library:
//
//   plugin.cpp:      LOOM_PLUGIN("warp", "ImageWarp: IDW and RBF warping");
//   image_warp.cpp:  struct ImageWarp { ... };  LOOM_NODE(ImageWarp);
//
// LOOM_NODE adds a node type to this library's list; LOOM_PLUGIN exports the
// one extern "C" entry point that hands the list to the engine. Plugins build
// with hidden visibility (loom_add_plugin does that), so each library's list
// is its own.
#pragma once

#include <vector>

#include "loom/registry.hpp"

// Bump whenever a header under loom/ changes in a way that breaks binary
// compatibility (a class layout, a virtual function, a signature).
// (A test overrides it to build a plugin the loader must refuse.)
#ifndef LOOM_ABI_VERSION
#define LOOM_ABI_VERSION 8
#endif

extern "C" {
struct LoomPluginEntry {
  int abi_version;
  const char* name;
  const char* description;
  void (*register_nodes)(loom::Registry& registry);
};
}

namespace loom::detail {
inline std::vector<NodeType>& plugin_node_list() {
  static std::vector<NodeType> list;
  return list;
}
template <class Node>
struct NodeRegistrar {
  NodeRegistrar() {
    NodeType t;
    t.spec.name = Node::name;
    Node::declare(t.spec);
    t.run = &Node::run;
    plugin_node_list().push_back(std::move(t));
  }
};
}  // namespace loom::detail

#define LOOM_CONCAT_INNER(a, b) a##b
#define LOOM_CONCAT(a, b) LOOM_CONCAT_INNER(a, b)

#define LOOM_NODE(NodeClass)                                                  \
  static const ::loom::detail::NodeRegistrar<NodeClass> LOOM_CONCAT(          \
      loom_node_registrar_, __LINE__)

#define LOOM_PLUGIN(NAME, DESCRIPTION)                                          \
  static void loom_register_plugin_nodes(::loom::Registry& registry) {          \
    for (const auto& t : ::loom::detail::plugin_node_list()) registry.add(t, NAME); \
  }                                                                             \
  extern "C" LOOM_EXPORT const LoomPluginEntry* loom_plugin() {                 \
    static const LoomPluginEntry entry{LOOM_ABI_VERSION, NAME, DESCRIPTION,     \
                                       &loom_register_plugin_nodes};            \
    return &entry;                                                              \
  }
