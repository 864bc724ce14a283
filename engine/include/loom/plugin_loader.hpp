// Host API. Finding and loading plugins.
//
// Each plugin library libloom_NAME.so has a manifest beside it,
// libloom_NAME.loom.json, written at build time: {"plugin", "abi", "nodes"}.
// A run reads the manifests and loads only the libraries whose node types its
// graph uses, so a graph without images never loads OpenCV.
//
// Search path: the plugin folder of this build or install
// (<bin>/../lib/loom/plugins), then each folder of LOOM_PLUGIN_PATH.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "loom/registry.hpp"

namespace loom {

LOOM_API int engine_abi_version();

class LOOM_API PluginLoadError : public Error {
 public:
  using Error::Error;
};

struct PluginInfo {
  std::string name;
  std::string description;
  std::filesystem::path library;
  std::vector<std::string> node_types;  // from the manifest (or the library)
  // Types with this prefix are provided on demand (loom/plugin_provider.hpp).
  std::string type_prefix;
  bool loaded = false;
};

class LOOM_API PluginLoader {
 public:
  explicit PluginLoader(Registry& registry);
  PluginLoader(Registry& registry, std::vector<std::filesystem::path> search_path);

  // The default search path: the folder next to the running executable, then
  // the absolute folders of LOOM_PLUGIN_PATH (relative entries are ignored
  // with a warning on stderr).
  static std::vector<std::filesystem::path> default_search_path();

  const std::vector<std::filesystem::path>& search_path() const { return search_path_; }
  const std::vector<PluginInfo>& plugins() const { return plugins_; }
  std::string searched_description() const;  // for "unknown node type" errors
  // Every node type known without loading more: the registry's and those the
  // manifests of plugins not loaded name (for "did you mean").
  std::vector<std::string> known_node_types() const;
  // Entries of the search path that cannot hold plugins: missing, or files.
  std::vector<std::string> search_path_warnings() const;

  // Loads the plugins that provide these node types; a type no manifest names
  // but a provider's prefix matches is asked of that provider. Other types
  // are left for validation to report; libraries without a manifest, which
  // may provide them, are loaded only when LOOM_LOAD_UNLISTED=1 (loading runs
  // a library's constructors before any check). Throws PluginLoadError.
  void load_for(const std::vector<std::string>& node_types);
  void load_all();
  // Loads one library by path (manifest or not).
  void load_library(const std::filesystem::path& library);

  std::vector<std::string> loaded_names() const;  // in load order

  // Hot reload (a plugin author's edit-build-look loop in the editor): loads
  // the loaded plugin `name` again from its rebuilt library file and puts the
  // new build's node types in the registry in place of the old ones, with a
  // new NodeSpec::build, so no cache serves the old build's results for them
  // or for what they feed. The file is loaded from a private copy (for the
  // same path the dynamic linker would return the old mapping); the old
  // library stays loaded, so values it made stay valid. The other plugins'
  // types are kept (as copies). Nothing may read the registry meanwhile (no
  // evaluation running). Throws PluginLoadError, leaving everything as it
  // was, when the new build does not load or clashes with another plugin.
  void reload(const std::string& name);

  // The manifest of a library, read by loading it: what the build writes.
  static json manifest_of(const std::filesystem::path& library, Registry& scratch);

 private:
  void scan();
  void load(PluginInfo& info);
  void provide(PluginInfo& info, const std::string& type);
  Registry& registry_;
  std::vector<std::filesystem::path> search_path_;
  std::vector<PluginInfo> plugins_;
  std::vector<std::string> load_order_;
};

}  // namespace loom
