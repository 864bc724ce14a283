#include "cli/run_settings.hpp"

#include <cstdlib>
#include <iostream>

namespace loom::runner {

DiskCache::Options CacheSettings::options() const {
  DiskCache::Options o;
  o.dir = dir.empty() ? DiskCache::default_dir() : std::filesystem::path(dir);
  o.max_bytes = static_cast<std::uint64_t>(limit_mb * 1024 * 1024);
  o.min_seconds = min_seconds;
  if (min_seconds == 0) o.read_mb_per_s = 1e300;  // store every result, however cheap to recompute
  return o;
}

std::optional<FrameRange> parse_frame_range(const std::string& text) {
  FrameRange r;
  std::size_t dash = text.find('-', 1);  // a leading '-' is a sign
  try {
    std::size_t used = 0;
    r.first = std::stoi(text.substr(0, dash), &used);
    if (used != (dash == std::string::npos ? text.size() : dash)) return std::nullopt;
    r.last = r.first;
    if (dash != std::string::npos) {
      r.last = std::stoi(text.substr(dash + 1), &used);
      if (used != text.size() - dash - 1) return std::nullopt;
    }
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (r.last < r.first) return std::nullopt;
  return r;
}

std::optional<std::string> frame_count_problem(const FrameRange& range, const std::string& from) {
  long long limit = kMaxFramesPerRun;
  if (const char* text = std::getenv("LOOM_MAX_FRAMES"); text && *text) {
    char* end = nullptr;
    limit = std::strtoll(text, &end, 10);
    if (*end != '\0' || limit < 1) return std::string("LOOM_MAX_FRAMES=") + text + ": expected a whole number above 0";
  }
  const long long frames = static_cast<long long>(range.last) - range.first + 1;
  if (frames <= limit) return std::nullopt;
  return from + " " + std::to_string(range.first) + "-" + std::to_string(range.last) + " is " +
         std::to_string(frames) + " frames, more than the limit of " + std::to_string(limit) +
         " frames a run walks: give a shorter --frames A-B, or raise the limit with LOOM_MAX_FRAMES=N";
}

std::optional<LoadedGraph> load_for_run(const std::string& path, const std::vector<std::string>& sets, int* exit) {
  LoadedGraph g;
  try {
    g.graph = load_graph_file(path);
    for (const auto& s : sets) set_input(g.graph, s);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    *exit = kInvalid;
    return std::nullopt;
  }
  try {
    g.loader->load_for(node_types_used(g.graph));
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    *exit = kPluginError;
    return std::nullopt;
  }
  try {
    validate_graph(g.graph, *g.registry, g.loader->searched_description(), g.loader->known_node_types());
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    *exit = kInvalid;
    return std::nullopt;
  }
  return g;
}

}  // namespace loom::runner
