#include "plugin_watcher.hpp"

namespace loom::editor {

PluginWatcher::PluginWatcher(const PluginLoader& loader, Clock::duration settle) : settle_(settle) {
  for (const PluginInfo& p : loader.plugins())
    if (p.loaded) {
      const Stamp now = stamp(p.library);
      plugins_[p.name] = {p.library, now, now, Clock::now()};
    }
}

PluginWatcher::Stamp PluginWatcher::stamp(const std::filesystem::path& file) {
  std::error_code ec;
  Stamp s;
  s.size = std::filesystem::file_size(file, ec);
  if (ec) return {};  // missing (being replaced): a stamp of its own
  s.mtime = std::filesystem::last_write_time(file, ec);
  return s;
}

std::vector<std::string> PluginWatcher::rebuilt(Clock::time_point now) {
  std::vector<std::string> ready;
  if (now - last_poll_ < std::chrono::milliseconds(100)) return ready;
  last_poll_ = now;
  for (auto& [name, w] : plugins_) {
    const Stamp current = stamp(w.library);
    if (current != w.seen) {
      w.seen = current;
      w.seen_since = now;
    } else if (current != w.loaded && current.size > 0 && now - w.seen_since >= settle_) {
      ready.push_back(name);
    }
  }
  return ready;
}

void PluginWatcher::reloaded(const std::string& plugin) {
  auto it = plugins_.find(plugin);
  if (it != plugins_.end()) it->second.loaded = it->second.seen;
}

}  // namespace loom::editor
