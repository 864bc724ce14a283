// What the plugin loader can tell a user about its search: the node types it
// knows of, and path entries that cannot hold plugins.
#include <algorithm>

#include "loom/plugin_loader.hpp"

namespace loom {

namespace fs = std::filesystem;

std::vector<std::string> PluginLoader::known_node_types() const {
  std::vector<std::string> types;
  for (const NodeType* t : registry_.all()) types.push_back(t->spec.name);
  for (const auto& p : plugins_)
    for (const auto& t : p.node_types) types.push_back(t);
  std::sort(types.begin(), types.end());
  types.erase(std::unique(types.begin(), types.end()), types.end());
  return types;
}

std::vector<std::string> PluginLoader::search_path_warnings() const {
  std::vector<std::string> warnings;
  for (const fs::path& dir : search_path_) {
    std::error_code ec;
    const fs::file_status status = fs::status(dir, ec);
    if (!fs::exists(status))
      warnings.push_back(dir.string() + " does not exist");
    else if (!fs::is_directory(status))
      warnings.push_back(dir.string() + " is a file, not a folder: name the folder that holds libloom_NAME.so" +
                         (dir.parent_path().empty() ? "" : " (" + dir.parent_path().string() + " perhaps)"));
  }
  return warnings;
}

}  // namespace loom
