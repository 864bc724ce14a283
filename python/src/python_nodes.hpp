// Node types whose body is a Python function (@loom.node). Each declared type
// owns one of kSlots run functions (the engine's RunFunction is a plain
// function pointer, so the slot number tells the body which function to
// call). A body takes the GIL, converts its inputs to Python (values.hpp),
// calls the function and converts what it returns; only the Python bodies
// share the GIL, C++ nodes run beside them.
#pragma once

#include <pybind11/pybind11.h>

#include "loom/registry.hpp"

namespace loom::python {

namespace py = pybind11;

constexpr int kSlots = 512;

// Runs in progress in this process: node types are declared only while there
// are none (a run reads the registry from its threads).
struct ActiveRun {
  ActiveRun();
  ~ActiveRun();
};

// Raises KeyboardInterrupt in every thread now running a Python body (the
// caller holds the GIL): a cancelled run's bodies stop at their next bytecode,
// also those that never ask ctx.cancelled(). A body inside one long C call
// (a time.sleep) stops when the call returns. Where no Python code waits for
// Ctrl-C (`loom run`, the editor), a thread started with the first body does
// the same for each body whose run is cancelled, within 20 ms.
void interrupt_python_bodies();

// Adds every Python node type declared so far to a registry (and remembers
// it, so that later declarations reach it too).
void register_python_nodes(Registry& registry);

// The `python` plugin's provider: imports the module a "py.MODULE.NAME" type
// names from the Python node path and adds its node types to `registry`.
// Holds the GIL. Throws loom::Error when the module cannot be imported.
void provide_python_nodes(Registry& registry, const std::string& type);

void bind_python_nodes(py::module_& m);

}  // namespace loom::python
