#include "cli/profile.hpp"

#include "loom/error.hpp"

namespace loom::runner {

const char* status_text(const NodeReport& r, const EvalResult& result) {
  const bool stopped = result.cancelled && r.status == NodeStatus::failed && r.error == Cancelled().what();
  return stopped ? "cancelled" : to_string(r.status);
}

json profile_json(const Graph& graph, const EvalResult& result, double total_seconds,
                  const std::vector<std::string>& plugins_loaded, const DiskCache* disk) {
  json nodes = json::object();
  for (const auto& [id, r] : result.nodes) {
    json j = {{"type", graph.nodes.at(id).type},
              {"status", status_text(r, result)},
              {"seconds", r.seconds},
              {"compute_seconds", r.compute_seconds},
              {"runs", r.runs}};
    if (r.status == NodeStatus::cached) j["source"] = r.runs == 0 && r.disk_hits > 0 ? "disk" : "memory";
    if (r.disk_hits > 0) j["disk_hits"] = r.disk_hits;
    if (r.memory_hits > 0) j["memory_hits"] = r.memory_hits;
    if (!r.error.empty()) j["error"] = r.error;
    if (!r.warnings.empty()) j["warnings"] = r.warnings;
    nodes[id] = j;
  }
  json profile = {{"total_seconds", total_seconds},
                  {"frames", result.frames},
                  {"plugins_loaded", plugins_loaded},
                  {"nodes", nodes}};
  if (disk)
    profile["disk_cache"] = {{"dir", disk->options().dir.string()},
                             {"bytes_read", disk->bytes_read()},
                             {"bytes_written", disk->bytes_written()},
                             {"read_seconds", disk->read_seconds()}};
  return profile;
}

}  // namespace loom::runner
