// Internal: a graph's "time" object, read and written, and the frame time an
// evaluation of the graph starts from.
#pragma once

#include "loom/evaluator.hpp"
#include "loom/graph.hpp"

namespace loom::detail {

// The "time" object; throws GraphError with /time pointers.
TimeRange parse_time(const json& t);
json time_to_json(const TimeRange& r);

// The graph's start frame and rate (frame 1 at 24 fps without "time"); the
// frame being evaluated is the caller's to set.
FrameTime graph_time(const Graph& graph);

}  // namespace loom::detail
