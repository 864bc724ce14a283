// `loom run --watch`: run the graph, then again whenever the graph file or an
// input file it reads changes, saying what changed; Ctrl-C ends it.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace loom::runner {

// The graph file and every input file its nodes read (inputs declared
// input_file with a path given in the graph, resolved against its folder).
// Only the graph file when it cannot be parsed or its plugins not loaded.
std::vector<std::filesystem::path> files_read(const std::filesystem::path& graph_file);

// Calls run_once, then waits for a change to files_read(graph_file) through
// inotify on their folders (an editor that saves by renaming a new file into
// place is seen too), prints which files changed and runs again. Returns when
// `cancel` is set: run_once's exit code when it was set during a run (130:
// interrupted), 0 when it was set while waiting; 2 after the first run when
// inotify cannot be used.
int watch(const std::filesystem::path& graph_file, const std::atomic<bool>& cancel,
          const std::function<int()>& run_once);

}  // namespace loom::runner
