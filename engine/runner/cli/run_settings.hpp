// What `loom run` was asked, for the front ends beside it (sweeps, submit).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "loom/disk_cache.hpp"
#include "loom/evaluator.hpp"
#include "loom/graph.hpp"
#include "loom/plugin_loader.hpp"

#include "cli/exit_codes.hpp"

namespace loom::runner {

// Where the persistent cache lives and how it behaves (`--cache`,
// `--cache-limit`, `--no-cache`, `--cache-min-seconds`, `--cache-no-trim`).
struct CacheSettings {
  std::string dir;  // empty: the default folder
  bool disabled = false;
  bool no_trim = false;  // a farm worker: the assemble task trims
  double limit_mb = 10240;
  double min_seconds = 0.05;

  DiskCache::Options options() const;
};

// What `loom run` was asked (its command line), for run, sweeps and MPI.
struct RunSettings {
  std::string graph_path;
  std::string out_dir = "out";
  std::vector<std::string> sets, targets;
  int threads = 0;
  bool quiet = false;
  bool print_json = false;  // --json
  std::string frames;  // "A-B", "A" or empty: the graph's range
  CacheSettings cache;
  bool allow_outside = false;
  std::string profile_path;  // --profile: empty for none
  std::string preview_path;  // --preview: empty for none (cli/preview.hpp)
  double preview_every = 1;  // --preview-every, seconds
};

// "A-B" or "A": the frames to run; nullopt when malformed.
std::optional<FrameRange> parse_frame_range(const std::string& text);

// Frames one run, sweep point or submitted job may walk (LOOM_MAX_FRAMES
// raises it): a "time" range of 1 to 1e9 ran 3.3 million cheap frames in
// 20 s without a word, 100 minutes in all; a million frames is 11.6 hours
// of video at 24 fps.
constexpr long long kMaxFramesPerRun = 1000000;
// Why `range` (from `from`: "--frames" or the graph's "time") may not run,
// naming the limit and how to raise it; nullopt when it may.
std::optional<std::string> frame_count_problem(const FrameRange& range, const std::string& from);

// A graph with its --set values applied, its plugins loaded and validated.
struct LoadedGraph {
  std::unique_ptr<Registry> registry = std::make_unique<Registry>();
  std::unique_ptr<PluginLoader> loader = std::make_unique<PluginLoader>(*registry);
  Graph graph;
};
// Loads as `loom run` does; on failure prints the error and returns the exit
// code (kInvalid or kPluginError) in *exit.
std::optional<LoadedGraph> load_for_run(const std::string& path, const std::vector<std::string>& sets, int* exit);

}  // namespace loom::runner
