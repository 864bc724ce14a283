// Plugin author API. A node's input file that is not there: the error names the closest existing
// names in its folder ("balls.obj": did you mean "Balls.obj"?) and how a
// relative path was resolved, so a typo or a wrong folder is one glance away.
#pragma once

#include <filesystem>
#include <string>

#include "loom/export.hpp"

namespace loom {

// Throws loom::Error unless `path` (an input_file input as the node receives
// it: already resolved, or a file named inside another) is a regular file:
//   cannot read mesh /g/balls.obj: no such file; did you mean "Balls.obj"?
//   (a relative path is resolved against the graph file's folder, /g)
// `what` names the kind of file ("mesh"); `graph_dir` is Context::graph_dir()
// (empty: no note on how the path was resolved). A missing folder is named as
// such, with the near names of that folder; a FIFO, socket or device is
// refused before anything opens it (open() on a FIFO blocks forever).
LOOM_API void require_input_file(const std::filesystem::path& path, const std::string& what,
                                 const std::filesystem::path& graph_dir = {});

// What stands at `path` when it exists but is not a regular file ("a
// directory", "a FIFO (named pipe)", a device, a socket), or "": for a message
// that names it, before anything opens it.
LOOM_API std::string not_a_regular_file(const std::filesystem::path& path);

}  // namespace loom
