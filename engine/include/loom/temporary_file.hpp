// Plugin author API. Staging files that never outlive the process that made them, short of
// SIGKILL: a TemporaryFile removes itself when destroyed uncommitted, and every
// live one is listed where a signal handler can reach it
// (remove_temporary_files, async-signal-safe), so a runner that is told to
// stop by SIGINT, SIGTERM, SIGHUP or SIGPIPE leaves none behind.
//
// Staging names are short and fixed in shape, ".loomtmp-<pid>-<n><ext>" in the
// target's folder, so a target name of up to 255 bytes (the file system's
// limit) can always be staged, and a folder's owner (the disk cache) can tell
// staging files from anything else.
#pragma once

#include <filesystem>
#include <string>

#include "loom/export.hpp"

namespace loom {

class LOOM_API TemporaryFile {
 public:
  // A new staging name beside `target` (no file is created). `extension`
  // ends the name (OpenCV chooses a video container by it).
  explicit TemporaryFile(std::filesystem::path target, const std::string& extension = {});
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& target() const { return target_; }
  // Renames the staging file over the target; throws loom::Error naming the
  // target (the staging file is then removed).
  void commit();
  // Removes the staging file now (also done by the destructor).
  void discard() noexcept;

 private:
  std::filesystem::path target_, path_;
  int slot_ = -1;
  bool done_ = false;
};

// True for a name TemporaryFile makes (".loomtmp-<digits>-<digits>...").
LOOM_API bool is_staging_name(const std::string& file_name);

// Unlinks every staging file of this process that is not committed. Safe in a
// signal handler (no allocation, no locks).
LOOM_API void remove_temporary_files() noexcept;

}  // namespace loom
