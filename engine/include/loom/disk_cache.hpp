// Host API. The persistent result cache: node results kept on disk between runs.
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
// size limit. What is stored is worth_storing()'s rule: reading back must be
// clearly cheaper than computing again, per frame and over the whole run.
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
    // What is stored, see worth_storing(). A node's time over the frames of
    // the run must reach min_seconds (below it a rerun saves too little to
    // be worth a file)...
    double min_seconds = 0.05;
    // ...reading one result back, read_entry_seconds plus its bytes at
    // read_mb_per_s (bench_engine_cache, docs/time.md), must take at most half
    // its compute time...
    double read_entry_seconds = 1e-4;
    double read_mb_per_s = 300;
    // ...and the run's frames of it together at most this share of max_bytes
    // (a larger sequence would push its own first frames out before a rerun).
    double max_sequence_share = 0.25;
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
  // Stores the values if every one's type is storable and worth_storing()
  // says so: `compute_seconds` is what recomputing them costs (for a
  // simulation state: the steps since its last stored state), `frames` how
  // many frames of the run the node computes a result like it (1 for a node
  // that does not depend on time). Returns the bytes written (0: not
  // stored). Never throws: a full disk only loses the entry.
  std::uint64_t store(std::uint64_t key, const std::vector<Value>& values, double compute_seconds = 1e300,
                      int frames = 1);

  // The storage rule: a result of `bytes` that took `compute_seconds` to
  // compute, at each of `frames` frames of the run, is stored when
  //   frames * compute_seconds >= min_seconds,
  //   2 * expected_read_seconds(bytes) <= compute_seconds,
  //   frames * bytes <= max_sequence_share * max_bytes.
  bool worth_storing(std::uint64_t bytes, double compute_seconds, int frames = 1) const;
  // What reading an entry of `bytes` back costs, by the measured model.
  double expected_read_seconds(std::uint64_t bytes) const;

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
