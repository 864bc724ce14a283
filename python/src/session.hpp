#pragma once

#include <memory>
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
  ~SessionCore();
  SessionCore(const SessionCore&) = delete;
  SessionCore& operator=(const SessionCore&) = delete;
  // Evaluates a validated graph (a PreparedGraph): {"outputs": {node:
  // [values]}, "nodes": {id: report}, "seconds", "frames", "cancelled"}.
  // progress(kind, node, fraction, text) is called on this thread. Ctrl-C
  // raises KeyboardInterrupt at once; the cancelled run ends on its own
  // thread (settle() waits for it, as every later call does).
  py::dict run(const py::object& prepared, const std::vector<std::string>& targets,
               std::optional<std::pair<int, int>> frames, const py::object& progress);
  void settle();

 private:
  struct Running;
  std::shared_ptr<Running> finishing;  // an interrupted run still ending
};

void bind_session(py::module_& m);

}  // namespace loom::python
