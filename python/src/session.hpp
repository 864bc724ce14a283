#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/pybind11.h>

#include "loom/disk_cache.hpp"
#include "loom/evaluator.hpp"
#include "graph_io.hpp"

namespace loom::python {

namespace py = pybind11;

struct SessionCore {
  Session session;
  int threads = 0;
  std::optional<DiskCache> disk;
  std::string output_dir;
  bool allow_outside_output = false;

  // disk_cache: unset none, "" the default folder, else that folder.
  SessionCore(int threads, std::optional<std::string> disk_cache, std::string output_dir,
              bool allow_outside_output);
  // Evaluates a validated graph: {"outputs": {node: [values]}, "nodes":
  // {id: report}, "seconds", "frames", "cancelled"}. progress(kind, node,
  // fraction, text) is called on this thread.
  py::dict run(const PreparedGraph& prepared, const std::vector<std::string>& targets,
               std::optional<std::pair<int, int>> frames, const py::object& progress);
};

void bind_session(py::module_& m);

}  // namespace loom::python
