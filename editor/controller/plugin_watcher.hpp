// Hot reload's eyes: watches the library files of the loaded plugins and
// says which were rebuilt. A file counts as rebuilt once its size and
// modification time differ from the loaded build's and then hold still for a
// moment (a linker still writing it would give a library that does not load).
// Polls with stat(): a dozen plugins cost microseconds, and it works the same
// for plugins on any file system and for linkers that replace the file.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "loom/plugin_loader.hpp"

namespace loom::editor {

class PluginWatcher {
 public:
  using Clock = std::chrono::steady_clock;
  // Takes the current files of the loader's loaded plugins as the loaded builds.
  explicit PluginWatcher(const PluginLoader& loader, Clock::duration settle = std::chrono::milliseconds(300));
  // The plugins rebuilt since they were loaded (or last reloaded), ready to
  // load again. Cheap enough to call every frame (stats at most every 100 ms).
  std::vector<std::string> rebuilt(Clock::time_point now = Clock::now());
  // The plugin's current file is the loaded build now.
  void reloaded(const std::string& plugin);

 private:
  struct Stamp {
    std::uintmax_t size = 0;
    std::filesystem::file_time_type mtime{};
    bool operator==(const Stamp& o) const { return size == o.size && mtime == o.mtime; }
    bool operator!=(const Stamp& o) const { return !(*this == o); }
  };
  struct Watched {
    std::filesystem::path library;
    Stamp loaded, seen;
    Clock::time_point seen_since{};
  };
  static Stamp stamp(const std::filesystem::path& file);
  std::map<std::string, Watched> plugins_;
  Clock::duration settle_;
  Clock::time_point last_poll_{};
};

}  // namespace loom::editor
