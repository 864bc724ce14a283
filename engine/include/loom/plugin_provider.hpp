// Plugin author API. Node types provided on demand, by name: for plugins whose types are not
// known when the plugin is built (the `python` plugin's nodes live in .py
// files on a search path).
//
// Such a plugin exports, besides loom_plugin (loom/plugin.hpp):
//
//   extern "C" LOOM_EXPORT const LoomPluginProvider* loom_plugin_provider();
//
// Its manifest then records the prefix ("type_prefix"), and a run whose graph
// uses a type starting with that prefix which no manifest lists loads the
// plugin and calls provide(registry, type). provide adds that type (and any
// others it finds on the way) to the registry, or nothing if there is no such
// type (validation then reports it, with "did you mean"); it throws
// loom::Error when it cannot look (a module that fails to import). Graphs
// without such a type never load the plugin.
#pragma once

#include "loom/registry.hpp"

extern "C" {
struct LoomPluginProvider {
  const char* type_prefix;  // e.g. "py."; never empty
  void (*provide)(loom::Registry& registry, const char* type);
};
}
