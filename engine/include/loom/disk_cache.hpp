// The persistent result cache: node results kept on disk between runs.
//
// An entry is one file, <dir>/<2 hex>/<16 hex key>.loomcache, named by
//   key = H(computation hash, the plugin library's build identity,
//           libloom's build identity)
// so a rebuilt plugin or engine never serves a previous build's results. The
// file is a header (magic, format version, key, value count, payload size,
// payload checksum) then the payload: per output value, its type name, the
// type's serial_version and its bytes (TypeInfo::write). Writes go to a
// temporary file renamed into place, so concurrent processes see a whole entry
// or none; a read checks sizes and the 64-bit checksum, and an entry that
// fails (corrupt, truncated, an old type version) is deleted and reported, and
// the caller recomputes. Reading an entry touches its modification time;
// trim() removes the least recently used entries until the folder is under its
// size limit. Only results whose node took at least min_seconds, and which
// read back in at most half their compute time, are stored.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "loom/value.hpp"

namespace loom {

class LOOM_API DiskCache {
 public:
  struct Options {
    std::filesystem::path dir;                     // created when missing
    std::uint64_t max_bytes = std::uint64_t(10) << 30;
    double min_seconds = 0.05;                     // store only results slower than this...
    // ...and only if reading them back (at this rate, measured on a loaded
    // machine by bench_engine_cache) takes at most half the compute time.
    double read_mb_per_s = 150;
  };
  explicit DiskCache(Options options);

  // $XDG_CACHE_HOME/loom, else $HOME/.cache/loom.
  static std::filesystem::path default_dir();

  const Options& options() const { return options_; }
  // The key of a result: its computation hash and the producing plugin's build.
  std::uint64_t key(std::uint64_t computation_hash, std::uint64_t plugin_build) const;

  bool contains(std::uint64_t key) const;
  // The stored values, or nullopt on a miss. An entry that cannot be read is
  // deleted and *problem says why (the caller warns and recomputes).
  std::optional<std::vector<Value>> load(std::uint64_t key, std::string* problem = nullptr);
  // Stores the values if every one's type is storable and they took long
  // enough to compute (`compute_seconds`, see Options); returns the bytes
  // written (0: not stored). Never throws: a full disk only loses the entry.
  std::uint64_t store(std::uint64_t key, const std::vector<Value>& values, double compute_seconds = 1e300);

  // The checksum an entry carries of its payload.
  static std::uint64_t checksum(const char* data, std::size_t size);

  struct Stats {
    std::uint64_t entries = 0, bytes = 0;
  };
  Stats stats() const;
  // Removes least recently used entries until the total is at most max_bytes,
  // and temporary files abandoned by killed processes.
  void trim();
  void clear();

  // Totals of this process, for benchmarks and the profile.
  std::uint64_t bytes_read() const { return bytes_read_; }
  std::uint64_t bytes_written() const { return bytes_written_; }
  double read_seconds() const { return read_nanoseconds_ * 1e-9; }

 private:
  std::filesystem::path path_of(std::uint64_t key) const;
  Options options_;
  std::uint64_t engine_build_ = 0;
  std::atomic<std::uint64_t> bytes_read_{0};
  std::atomic<std::uint64_t> bytes_written_{0};
  std::atomic<std::uint64_t> read_nanoseconds_{0};
};

}  // namespace loom
