#pragma once

#include <string>
#include <vector>

#include <pybind11/pybind11.h>

#include "held_value.hpp"
#include "loom/graph.hpp"

namespace loom::python {

namespace py = pybind11;

// A graph ready for Session.run: parsed, --set values applied, in-memory
// values linked (and held until it is dropped), plugins loaded, validated.
struct PreparedGraph {
  Graph graph;
  HeldValues held;
};

void bind_graph_io(py::module_& m);

}  // namespace loom::python
