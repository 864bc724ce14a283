// A job's copy of a graph: the graph file and every group file it uses,
// written into the job folder so that a task runs with only the job folder,
// Loom and the input files (docs/farm.md, "The job folder").
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "loom/graph_view.hpp"

namespace loom::runner {

// Writes JOB/graph.json (the graph's own document) and JOB/groups/H/NAME.json
// for each group file it uses (H: a digest of the file's path, so two files
// of one name never meet; NAME kept, as it names the group). References are
// rewritten to the copies; inline groups, ids, values and layout are kept as
// written, so each task loads the same graph as `loom run` of the original.
// Relative input file paths are made absolute (a copy lives elsewhere).
void write_bundle(const GraphView& view, const Registry& registry, const std::filesystem::path& job);

// A --set assignment as a task is given it: a relative path given to an input
// file made absolute against the graph's folder, anything else as written.
std::string task_assignment(const GraphView& view, const std::string& assignment);

}  // namespace loom::runner
