// The `python` plugin: node types written in Python (@loom.node), for `loom
// run` and the editor. Its manifest names no types but the prefix "py.", so
// only a graph using a "py.MODULE.NAME" type loads it; only then is the
// interpreter started (in python-embed.so, which needs Python's symbols: from
// the process when it is Python itself, else from libpython, loaded here).
#include <dlfcn.h>

#include <filesystem>
#include <string>

#include "loom/plugin.hpp"
#include "loom/plugin_provider.hpp"

LOOM_PLUGIN("python", "Nodes written in Python (@loom.node), imported from the Python node path");

namespace {

namespace fs = std::filesystem;

fs::path this_folder() {
  Dl_info info{};
  ::dladdr(reinterpret_cast<void*>(&this_folder), &info);
  return fs::absolute(info.dli_fname ? info.dli_fname : ".").parent_path();
}

// Where the `loom` package is, relative to this plugin: build/lib/loom/plugins
// -> build/python; <prefix>/lib/loom/plugins -> <prefix>/lib/python3.X/dist-packages.
std::string package_folders(const fs::path& here) {
  std::string folders;
  for (const fs::path& p : {here / ".." / ".." / ".." / "python", here / ".." / ".." / LOOM_PYTHON_SITE_DIR}) {
    std::error_code ec;
    if (fs::is_directory(p / "loom", ec)) folders += (folders.empty() ? "" : ":") + p.lexically_normal().string();
  }
  return folders;
}

void provide(loom::Registry& registry, const char* type) {
  if (!::dlsym(RTLD_DEFAULT, "Py_IsInitialized") && !::dlopen(LOOM_LIBPYTHON, RTLD_NOW | RTLD_GLOBAL))
    throw loom::Error(std::string("cannot load the Python library " LOOM_LIBPYTHON " for Python node type \"") +
                      type + "\": " + ::dlerror() + " (install python3-dev)");
  const fs::path here = this_folder();
  const fs::path helper = here / "python-embed.so";
  void* handle = ::dlopen(helper.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw loom::Error("cannot load " + helper.string() + ": " + ::dlerror());
  using Embed = void (*)(loom::Registry&, const char*, const char*);
  auto embed = reinterpret_cast<Embed>(::dlsym(handle, "loom_python_embed_provide"));
  if (!embed) throw loom::Error(helper.string() + " has no loom_python_embed_provide");
  embed(registry, type, package_folders(here).c_str());
}

}  // namespace

extern "C" LOOM_EXPORT const LoomPluginProvider* loom_plugin_provider() {
  static const LoomPluginProvider provider{"py.", &provide};
  return &provider;
}
