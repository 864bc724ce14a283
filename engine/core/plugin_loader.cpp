#include "loom/plugin_loader.hpp"

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <fstream>
#include <iostream>

#include <dlfcn.h>
#include <unistd.h>

#include "build_identity.hpp"
#include "loom/plugin.hpp"
#include "loom/plugin_provider.hpp"
#include "loom/search_path.hpp"

namespace loom {

namespace fs = std::filesystem;

int engine_abi_version() { return LOOM_ABI_VERSION; }

namespace {

const std::string kPrefix = "libloom_";
const std::string kSuffix = ".so";

bool is_plugin_file(const fs::path& p) {
  std::string f = p.filename().string();
  return f.size() > kPrefix.size() + kSuffix.size() && f.compare(0, kPrefix.size(), kPrefix) == 0 &&
         f.compare(f.size() - kSuffix.size(), kSuffix.size(), kSuffix) == 0;
}

fs::path manifest_path(const fs::path& library) {
  fs::path m = library;
  return m.replace_extension(".loom.json");
}

const LoomPluginEntry* open_entry(const fs::path& library) {
  void* handle = ::dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle)
    throw PluginLoadError("cannot load plugin library " + library.string() + ": " + ::dlerror());
  auto entry_fn = reinterpret_cast<const LoomPluginEntry* (*)()>(::dlsym(handle, "loom_plugin"));
  if (!entry_fn)
    throw PluginLoadError(library.string() +
                          " is not a Loom plugin: it has no loom_plugin entry point (LOOM_PLUGIN)");
  const LoomPluginEntry* entry = entry_fn();
  if (entry->abi_version != LOOM_ABI_VERSION)
    throw PluginLoadError("plugin \"" + std::string(entry->name) + "\" (" + library.string() +
                          ") was built for Loom plugin ABI " + std::to_string(entry->abi_version) +
                          ", but this Loom has ABI " + std::to_string(LOOM_ABI_VERSION) +
                          ": rebuild the plugin against this Loom's SDK (find_package(loom) "
                          "from the same install as this loom)");
  return entry;
}

// The provider of a plugin that has one (loom/plugin_provider.hpp), or null.
const LoomPluginProvider* open_provider(const fs::path& library) {
  void* handle = ::dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) return nullptr;
  auto fn = reinterpret_cast<const LoomPluginProvider* (*)()>(::dlsym(handle, "loom_plugin_provider"));
  return fn ? fn() : nullptr;
}

bool unlisted_plugin(const PluginInfo& p) { return p.node_types.empty() && p.type_prefix.empty(); }

}  // namespace

PluginLoader::PluginLoader(Registry& registry) : PluginLoader(registry, default_search_path()) {}

PluginLoader::PluginLoader(Registry& registry, std::vector<fs::path> search_path)
    : registry_(registry), search_path_(std::move(search_path)) {
  scan();
}

std::vector<fs::path> PluginLoader::default_search_path() {
  std::vector<fs::path> path;
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) path.push_back((exe.parent_path() / ".." / "lib" / "loom" / "plugins").lexically_normal());
  for (fs::path& dir : search_path_from_env("LOOM_PLUGIN_PATH")) path.push_back(std::move(dir));
  return path;
}

void PluginLoader::scan() {
  for (const fs::path& dir : search_path_) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (is_plugin_file(e.path())) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& lib : files) {
      PluginInfo info;
      info.library = lib;
      info.name = lib.stem().string().substr(kPrefix.size());
      std::ifstream in(manifest_path(lib));
      if (in) {
        json m = json::parse(in, nullptr, false);
        if (!m.is_discarded() && m.is_object()) {
          info.name = m.value("plugin", info.name);
          info.description = m.value("description", "");
          if (m.contains("type_prefix") && m["type_prefix"].is_string())
            info.type_prefix = m["type_prefix"].get<std::string>();
          if (m.contains("nodes") && m["nodes"].is_array())
            for (const auto& n : m["nodes"])
              if (n.is_string()) info.node_types.push_back(n.get<std::string>());
        }
      }
      bool duplicate = false;  // the first folder on the path wins
      for (const auto& p : plugins_) duplicate = duplicate || p.name == info.name;
      if (!duplicate) plugins_.push_back(std::move(info));
    }
  }
}

void PluginLoader::load(PluginInfo& info) {
  if (info.loaded) return;
  const LoomPluginEntry* entry = open_entry(info.library);
  Registry staged;  // register into a copy first: a failing plugin adds nothing
  entry->register_nodes(staged);
  info.node_types.clear();
  // The library's content identity enters the disk cache's keys (NodeSpec::build).
  const std::uint64_t build = detail::build_identity(info.library);
  for (const NodeType* t : staged.all()) {
    NodeType copy = *t;
    copy.spec.build = build;
    registry_.add(std::move(copy), entry->name);
    info.node_types.push_back(t->spec.name);
  }
  info.name = entry->name;
  info.description = entry->description;
  info.loaded = true;
  load_order_.push_back(info.name);
}

void PluginLoader::load_for(const std::vector<std::string>& node_types) {
  bool unknown = false;
  for (const std::string& type : node_types) {
    if (registry_.find(type)) continue;
    PluginInfo* provider = nullptr;
    for (auto& p : plugins_)
      for (const auto& t : p.node_types)
        if (t == type && !provider) provider = &p;
    if (provider) {
      load(*provider);
      continue;
    }
    for (auto& p : plugins_)
      if (!provider && !p.type_prefix.empty() && type.compare(0, p.type_prefix.size(), p.type_prefix) == 0)
        provider = &p;
    if (provider) provide(*provider, type);
    else unknown = true;
  }
  // A library without a manifest may provide it, but loading one runs its
  // constructors before any check: only when asked (LOOM_LOAD_UNLISTED=1).
  const char* unlisted = std::getenv("LOOM_LOAD_UNLISTED");
  if (unknown && unlisted && std::string(unlisted) == "1")
    for (auto& p : plugins_)
      if (unlisted_plugin(p)) load(p);
}

void PluginLoader::provide(PluginInfo& info, const std::string& type) {
  load(info);
  const LoomPluginProvider* provider = open_provider(info.library);
  if (!provider)
    throw PluginLoadError("plugin \"" + info.name + "\" (" + info.library.string() +
                          ") has a type_prefix in its manifest but no loom_plugin_provider entry point");
  provider->provide(registry_, type.c_str());
}

void PluginLoader::load_all() {
  for (auto& p : plugins_) load(p);
}

void PluginLoader::load_library(const fs::path& library) {
  for (auto& p : plugins_)
    if (fs::equivalent(p.library, library)) return load(p);
  PluginInfo info;
  info.library = library;
  plugins_.push_back(info);
  load(plugins_.back());
}

std::vector<std::string> PluginLoader::loaded_names() const { return load_order_; }

void PluginLoader::reload(const std::string& name) {
  auto info =
      std::find_if(plugins_.begin(), plugins_.end(), [&](const PluginInfo& p) { return p.loaded && p.name == name; });
  if (info == plugins_.end()) throw PluginLoadError("cannot reload plugin \"" + name + "\": it is not loaded");
  // A private copy, removed once mapped: a new path and file for dlopen.
  std::string folder = (fs::temp_directory_path() / "loom-reload-XXXXXX").string();
  if (!::mkdtemp(folder.data()))
    throw PluginLoadError("cannot reload plugin \"" + name + "\": cannot make a temporary folder");
  const fs::path copy = fs::path(folder) / info->library.filename();
  std::error_code ec;
  const LoomPluginEntry* entry = nullptr;
  try {
    fs::copy_file(info->library, copy);
    entry = open_entry(copy);
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(folder, ec);
    throw PluginLoadError("cannot reload plugin \"" + name + "\": " + e.what());
  } catch (...) {
    fs::remove_all(folder, ec);
    throw;
  }
  fs::remove_all(folder, ec);
  Registry staged;
  entry->register_nodes(staged);
  Registry fresh;
  for (const NodeType* t : registry_.all())
    if (t->spec.plugin != name) fresh.add(*t, t->spec.plugin);
  const std::uint64_t build = detail::build_identity(info->library);
  std::vector<std::string> types;
  for (const NodeType* t : staged.all()) {
    NodeType type = *t;
    type.spec.build = build;
    fresh.add(std::move(type), name);  // throws on a clash: the registry is still the old one
    types.push_back(t->spec.name);
  }
  info->node_types = std::move(types);
  // The old types stay alive (never freed, like the old library): a value or
  // a report made by them may still point at them.
  static std::vector<std::unique_ptr<Registry>> retired;
  retired.push_back(std::make_unique<Registry>(std::move(registry_)));
  registry_ = std::move(fresh);
}

std::string PluginLoader::searched_description() const {
  std::string text = "searched plugins: ";
  bool first = true;
  for (const auto& p : plugins_) {
    text += (first ? "" : ", ") + p.name;
    first = false;
  }
  if (first) text += "none found";
  int without_manifest = 0;
  for (const auto& p : plugins_) without_manifest += unlisted_plugin(p) && !p.loaded;
  if (without_manifest > 0)
    text += " (" + std::to_string(without_manifest) +
            " without a manifest, not loaded: LOOM_LOAD_UNLISTED=1 loads them)";
  text += "; plugin path: ";
  first = true;
  for (const auto& d : search_path_) {
    text += (first ? "" : ":") + d.string();
    first = false;
  }
  return text;
}

json PluginLoader::manifest_of(const fs::path& library, Registry& scratch) {
  const LoomPluginEntry* entry = open_entry(library);
  entry->register_nodes(scratch);
  json nodes = json::array();
  for (const NodeType* t : scratch.all()) nodes.push_back(t->spec.name);
  json manifest = {{"plugin", entry->name},
                   {"description", entry->description},
                   {"abi", entry->abi_version},
                   {"nodes", nodes}};
  if (const LoomPluginProvider* provider = open_provider(library))
    manifest["type_prefix"] = provider->type_prefix;
  return manifest;
}

}  // namespace loom
