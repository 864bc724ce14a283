// python-embed.so: starts the interpreter in a process that is not Python
// (`loom run`, the editor) and asks the loom module for a Python node type.
// Built without libpython: its Python symbols come from the process, or from
// the libpython the `python` plugin loaded globally before loading this.
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <cstdlib>
#include <string>

#include "loom/registry.hpp"

namespace {

std::string python_error() {
  PyObject *type, *value, *trace;
  PyErr_Fetch(&type, &value, &trace);
  std::string text = "unknown error";
  if (PyObject* s = value ? PyObject_Str(value) : nullptr) {
    if (const char* c = PyUnicode_AsUTF8(s)) text = c;
    Py_DECREF(s);
  }
  Py_XDECREF(type);
  Py_XDECREF(value);
  Py_XDECREF(trace);
  return text;
}

// Started once, never finalized (node types and cached values refer to it
// until the process ends). Signal handlers stay the runner's: Ctrl-C cancels
// through the engine, not as a KeyboardInterrupt. The GIL is released at
// the end, for node bodies to take on the engine's threads.
//
// The interpreter is the one Loom was built for (LOOM_PYTHON_EXECUTABLE, whose
// libpython the plugin loaded): left to itself, Python takes its prefix from
// the first `python3` on PATH, and a venv or pyenv interpreter there has
// another standard library and no numpy — every Python node then failed with
// "could not import module loom" (issue 37). PYTHONHOME still overrides.
void start_interpreter() {
  PyConfig config;
  PyConfig_InitPythonConfig(&config);
  config.install_signal_handlers = 0;
  config.parse_argv = 0;
  PyStatus status = PyStatus_Ok();
  if (!std::getenv("PYTHONHOME"))
    status = PyConfig_SetBytesString(&config, &config.program_name, LOOM_PYTHON_EXECUTABLE);
  if (!PyStatus_Exception(status)) status = Py_InitializeFromConfig(&config);
  PyConfig_Clear(&config);
  if (PyStatus_Exception(status))
    throw loom::Error(std::string("cannot start Python: ") + (status.err_msg ? status.err_msg : "unknown error"));
  PyEval_SaveThread();
}

void add_to_sys_path(const std::string& folders) {
  PyObject* path = PySys_GetObject("path");  // borrowed
  std::size_t start = 0;
  while (path && start < folders.size()) {
    std::size_t end = folders.find(':', start);
    if (end == std::string::npos) end = folders.size();
    PyObject* entry = PyUnicode_FromStringAndSize(folders.data() + start, Py_ssize_t(end - start));
    if (entry && PySequence_Contains(path, entry) == 0) PyList_Insert(path, 0, entry);
    Py_XDECREF(entry);
    start = end + 1;
  }
}

struct Gil {
  PyGILState_STATE state = PyGILState_Ensure();
  ~Gil() { PyGILState_Release(state); }
};

}  // namespace

extern "C" __attribute__((visibility("default"))) void loom_python_embed_provide(loom::Registry& registry,
                                                                                  const char* type,
                                                                                  const char* package_folders) {
  if (!Py_IsInitialized()) start_interpreter();
  Gil gil;
  add_to_sys_path(package_folders);
  using Provide = void (*)(loom::Registry&, const char*);
  auto* provide = static_cast<Provide*>(PyCapsule_Import("loom._loom._provider", 0));
  if (!provide)
    throw loom::Error("cannot import the loom Python module (for node type \"" + std::string(type) +
                      "\"): " + python_error() + "; build it (pybind11-dev, python3-numpy) or set PYTHONPATH");
  (*provide)(registry, type);
}
