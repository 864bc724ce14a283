// loom._loom: the compiled half of `import loom` (the Python half is
// python/loom/*.py). Engine errors become loom.Error / loom.GraphError.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "graph_io.hpp"
#include "loom/graph.hpp"
#include "python_nodes.hpp"
#include "session.hpp"
#include "values.hpp"

namespace py = pybind11;

namespace {

void raise(const char* cls, py::object args) {
  py::object type = py::module_::import("loom._errors").attr(cls);
  PyErr_SetObject(type.ptr(), type(*args).ptr());
}

void translate(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const loom::GraphError& e) {
    py::list issues;
    for (const auto& i : e.issues()) issues.append(py::make_tuple(i.pointer, i.message));
    raise("GraphError", py::make_tuple(e.what(), e.file(), issues));
  } catch (const loom::Error& e) {
    raise("Error", py::make_tuple(e.what()));
  }
}

// What the `python` plugin calls through a capsule (python/plugin/embed.cpp).
void provide(loom::Registry& registry, const char* type) { loom::python::provide_python_nodes(registry, type); }
using ProvideFunction = void (*)(loom::Registry&, const char*);

}  // namespace

PYBIND11_MODULE(_loom, m) {
  m.doc() = "The compiled half of the loom module; use `import loom`.";
  loom::python::register_value_types();
  py::register_exception_translator(&translate);
  loom::python::bind_values(m);
  loom::python::bind_graph_io(m);
  loom::python::bind_session(m);
  loom::python::bind_python_nodes(m);
  static ProvideFunction provider = &provide;
  m.attr("_provider") = py::capsule(reinterpret_cast<void*>(&provider), "loom._loom._provider");
}
