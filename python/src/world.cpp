#include "world.hpp"

#include <dlfcn.h>

#include "loom/suggest.hpp"
#include "held_value.hpp"
#include "python_nodes.hpp"

namespace loom::python {

namespace fs = std::filesystem;

namespace {

// The plugin folder relative to this module's file: build/python/loom ->
// build/lib/loom/plugins; <prefix>/lib/python3.X/dist-packages/loom ->
// <prefix>/lib/loom/plugins.
std::vector<fs::path> module_plugin_path() {
  Dl_info info{};
  std::vector<fs::path> path;
  if (::dladdr(reinterpret_cast<void*>(&module_plugin_path), &info) && info.dli_fname) {
    const fs::path here = fs::absolute(info.dli_fname).parent_path();
    for (const fs::path& candidate : {here / ".." / ".." / "lib" / "loom" / "plugins",
                                      here / ".." / ".." / ".." / "loom" / "plugins"}) {
      std::error_code ec;
      if (fs::is_directory(candidate, ec)) {
        path.push_back(candidate.lexically_normal());
        break;
      }
    }
  }
  for (const fs::path& p : PluginLoader::default_search_path())
    if (p != fs::path("/usr/lib/loom/plugins") || path.empty()) path.push_back(p);
  return path;
}

}  // namespace

World::World() : loader(registry, module_plugin_path()) {
  registry.add(held_value_type(), "python");
  register_python_nodes(registry);
}

void World::load_for(const std::vector<std::string>& types) {
  std::lock_guard<std::recursive_mutex> lock(mutex);
  loader.load_for(types);
}

const NodeType& World::type(const std::string& name) {
  load_for({name});
  std::lock_guard<std::recursive_mutex> lock(mutex);
  if (const NodeType* t = registry.find(name)) return *t;
  throw Error(unknown_node_type_message(name, loader.known_node_types(), loader.searched_description()));
}

World& world() {
  static World* w = new World();  // never destroyed: plugins stay loaded until exit
  return *w;
}

}  // namespace loom::python
