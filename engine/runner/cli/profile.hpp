// `--profile FILE`: what a run did, per node, as JSON (docs/time.md).
#pragma once

#include <optional>

#include "loom/disk_cache.hpp"
#include "loom/evaluator.hpp"
#include "loom/graph.hpp"

namespace loom::runner {

// A node's status as a user is told it: "cancelled" for a node a cancelled
// run stopped (the engine reports it failed, its error "cancelled"), else
// the engine's word.
const char* status_text(const NodeReport& report, const EvalResult& result);

// The profile of one evaluation: per node its type, status, seconds (the
// body's time in this run), compute_seconds (what its results took to
// compute, cached ones included), runs and cache hits; the disk cache's
// traffic when one was used.
json profile_json(const Graph& graph, const EvalResult& result, double total_seconds,
                  const std::vector<std::string>& plugins_loaded, const DiskCache* disk);

}  // namespace loom::runner
