// The module's engine: one Registry and PluginLoader per Python process, as
// one `loom run` has, made on first use. Plugins are found beside the module
// (the build's or install's lib/loom/plugins), then in LOOM_PLUGIN_PATH.
#pragma once

#include <mutex>
#include <string>
#include <vector>

#include "loom/plugin_loader.hpp"

namespace loom::python {

struct World {
  Registry registry;
  PluginLoader loader;
  // Held by whoever reads or changes the registry (the GIL guards the rest;
  // evaluations only read the types they were validated with).
  std::recursive_mutex mutex;

  World();
  // Loads the plugins these types need (a Python node type imports its module).
  void load_for(const std::vector<std::string>& types);
  // The node type, loading its plugin first; throws loom::Error with "did you
  // mean" when nothing provides it.
  const NodeType& type(const std::string& name);
};

World& world();

}  // namespace loom::python
