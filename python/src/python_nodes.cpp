#include "python_nodes.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include "loom/builtin_types.hpp"
#include "loom/input_declaration.hpp"
#include "values.hpp"
#include "world.hpp"

namespace loom::python {

namespace {

struct PythonNode {
  NodeType type;
  py::object function;
  std::string module;
  bool wants_context = false;
};

// Guarded by the GIL: declared from Python, read by bodies holding the GIL.
std::vector<std::unique_ptr<PythonNode>>& nodes() {
  static auto* list = new std::vector<std::unique_ptr<PythonNode>>();  // outlives the interpreter
  return *list;
}
std::vector<Registry*>& registries() {
  static auto* list = new std::vector<Registry*>();
  return *list;
}

std::atomic<int> g_active_runs{0};

// What a Python body sees as `ctx`: valid only during its call.
struct PyContext {
  Context* ctx = nullptr;
  Context& get() const {
    if (!ctx) throw Error("the node context is used after its node returned");
    return *ctx;
  }
};

std::string python_error_text(py::error_already_set& e) {
  std::string text = std::string(py::str(e.type().attr("__name__"))) + ": " + py::str(e.value()).cast<std::string>();
  py::object tb = e.trace();
  std::string where;
  while (!tb.is_none()) {  // the innermost frame: where it was raised
    py::object code = tb.attr("tb_frame").attr("f_code");
    where = py::str(code.attr("co_filename")).cast<std::string>() + ":" +
            py::str(tb.attr("tb_lineno")).cast<std::string>() + " in " +
            py::str(code.attr("co_name")).cast<std::string>();
    tb = tb.attr("tb_next");
  }
  return where.empty() ? text : text + " (at " + where + ")";
}

// The returned object for each output, in declaration order.
std::vector<py::object> split_result(const py::object& result, const NodeSpec& spec) {
  const std::size_t n = spec.outputs.size();
  if (n == 1) return {result};
  std::vector<py::object> values;
  if (py::isinstance<py::dict>(result)) {
    py::dict d = result;
    for (const auto& o : spec.outputs) {
      if (!d.contains(o.name)) throw Error("the returned dict has no output \"" + o.name + "\"");
      values.push_back(d[py::str(o.name)]);
    }
  } else if (py::isinstance<py::tuple>(result) && py::len(result) == n) {
    for (const auto& v : result) values.push_back(py::reinterpret_borrow<py::object>(v));
  } else {
    throw Error("expected a tuple of " + std::to_string(n) + " values or a dict of outputs, got " +
                std::string(py::str(py::type::of(result).attr("__name__"))));
  }
  return values;
}

// The Python threads running a body now, with their node's context
// (interrupt_python_bodies, watch_cancellation). Lock order: the GIL, then
// the mutex (a body holds the GIL when it registers and leaves).
struct RunningBody;
struct Bodies {
  std::mutex mutex;
  std::set<RunningBody*> running;
};
Bodies& bodies() {
  static auto* b = new Bodies();  // never destroyed: the watch thread outlives static destruction
  return *b;
}

struct RunningBody {
  unsigned long ident = PyThread_get_thread_ident();
  const Context& ctx;
  bool interrupted = false;  // under bodies().mutex
  explicit RunningBody(const Context& c);
  ~RunningBody() {  // with the GIL held
    std::lock_guard lock(bodies().mutex);
    bodies().running.erase(this);
    // One raised after the body returned would fire in the next Python code
    // of this thread (another run's body): drop it.
    if (interrupted) PyThreadState_SetAsyncExc(ident, nullptr);
  }
  RunningBody(const RunningBody&) = delete;
  RunningBody& operator=(const RunningBody&) = delete;
};

// Raises KeyboardInterrupt, once, in each body whose run is cancelled; true if
// one was. The caller holds the mutex (and the GIL when `raise`).
bool interrupt_cancelled(bool raise) {
  bool any = false;
  for (RunningBody* b : bodies().running)
    if (!b->interrupted && b->ctx.cancelled()) {
      any = true;
      if (!raise) break;
      b->interrupted = true;
      PyThreadState_SetAsyncExc(b->ident, PyExc_KeyboardInterrupt);
    }
  return any;
}

// `loom run` and the editor have no Python code waiting for Ctrl-C (a Session
// has: SessionCore::run), so a thread started with the first body looks every
// 20 ms; without it a body that never asks ctx.cancelled() ran on until the
// runner's 5-s watchdog. The GIL is taken only when a body is to be stopped.
void watch_cancellation() {
  for (;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    {
      std::lock_guard lock(bodies().mutex);
      if (!interrupt_cancelled(false)) continue;
    }
    const PyGILState_STATE gil = PyGILState_Ensure();
    {
      std::lock_guard lock(bodies().mutex);
      interrupt_cancelled(true);
    }
    PyGILState_Release(gil);
  }
}

RunningBody::RunningBody(const Context& c) : ctx(c) {
  static std::once_flag watching;
  std::call_once(watching, [] { std::thread(watch_cancellation).detach(); });
  std::lock_guard lock(bodies().mutex);
  bodies().running.insert(this);
}

void run_python_node(int slot, Inputs& in, Outputs& out, Context& ctx) {
  py::gil_scoped_acquire gil;
  const RunningBody running(ctx);
  const PythonNode& node = *nodes().at(std::size_t(slot));
  const NodeSpec& spec = node.type.spec;
  py::dict kwargs;
  for (const auto& i : spec.inputs) kwargs[py::str(i.name)] = in.has(i.name) ? to_python(in.value(i.name)) : py::none();
  auto context = std::make_shared<PyContext>(PyContext{&ctx});
  if (node.wants_context) kwargs["ctx"] = py::cast(context);
  py::object result;
  try {
    result = node.function(**kwargs);
  } catch (py::error_already_set& e) {
    context->ctx = nullptr;
    if (ctx.cancelled()) throw Cancelled();
    throw Error(python_error_text(e));
  }
  context->ctx = nullptr;
  const std::vector<py::object> values = split_result(result, spec);
  for (std::size_t k = 0; k < values.size(); ++k) {
    const OutputSpec& o = spec.outputs[k];
    try {
      out.set_value(o.name, from_python(values[k], *o.type));
    } catch (const Error& e) {
      throw Error("output \"" + o.name + "\" (" + o.type->name + "): " + e.what());
    }
  }
}

template <std::size_t... I>
constexpr std::array<RunFunction, sizeof...(I)> make_slots(std::index_sequence<I...>) {
  return {[](Inputs& in, Outputs& out, Context& ctx) { run_python_node(int(I), in, out, ctx); }...};
}
const std::array<RunFunction, kSlots> kRunSlots = make_slots(std::make_index_sequence<kSlots>());

// An input declared by loom.In, in the engine's vocabulary (In.declaration).
InputSpec input_spec(const py::dict& d) {
  json declaration = to_json(d);
  const std::string name = declaration["name"];
  declaration.erase("name");
  try {
    const TypeInfo* type = find_type(declaration.value("type", std::string()));
    if (type && !type->literal() && declaration.contains("default"))
      throw Error("a " + type->name + " input cannot have a default");
    return input_spec_from_json(name, declaration);
  } catch (const Error& e) {
    throw Error("input \"" + name + "\": " + e.what());
  }
}

// The NodeType for a declaration; `version` is the source hash folded to
// 31 bits (the memory cache's key), `build` the whole hash (the disk cache's).
NodeType node_type(const std::string& name, const std::string& description, const py::list& inputs,
                   const py::list& outputs, const py::dict& flags, std::uint64_t source_hash, int slot) {
  NodeType t;
  t.spec.name = name;
  t.spec.describe(description);
  for (const auto& i : inputs) {
    InputSpec s = input_spec(i.cast<py::dict>());
    if (t.spec.find_input(s.name)) throw Error("input \"" + s.name + "\" is declared twice");
    t.spec.inputs.push_back(std::move(s));
  }
  for (const auto& o : outputs) {
    py::dict d = o.cast<py::dict>();
    t.spec.outputs.push_back({d["name"].cast<std::string>(), d["description"].cast<std::string>(),
                              &declared_type(d["type"].cast<std::string>())});
  }
  if (t.spec.outputs.empty() && !flags["sink"].cast<bool>())
    throw Error("a node needs at least one output (or sink=True)");
  if (flags["sink"].cast<bool>()) t.spec.set_sink();
  if (flags["time_dependent"].cast<bool>()) t.spec.set_time_dependent();
  if (flags["nondeterministic"].cast<bool>()) t.spec.set_nondeterministic();
  if (flags.contains("source_file")) t.spec.source_file = flags["source_file"].cast<std::string>();
  t.spec.version = int(source_hash & 0x7fffffff);
  t.spec.build = source_hash;
  t.run = kRunSlots[std::size_t(slot)];
  return t;
}

void add_to(Registry& registry, const NodeType& type) {
  if (NodeType* existing = const_cast<NodeType*>(registry.find(type.spec.name))) {
    // A redeclaration (a notebook cell run again): the registry owns its
    // types mutably; it is replaced between runs, never during one (see
    // ActiveRun), with the GIL held.
    const std::string plugin = existing->spec.plugin;
    *existing = type;
    existing->spec.plugin = plugin;
  } else {
    registry.add(type, "python");
  }
}

void declare_node(const std::string& name, const std::string& module, py::object function,
                  const std::string& description, const py::list& inputs, const py::list& outputs,
                  const py::dict& flags, std::uint64_t source_hash, bool wants_context) {
  if (g_active_runs > 0)
    throw Error("cannot declare node type \"" + name + "\" while a Session.run is in progress");
  auto& list = nodes();
  int slot = -1;
  for (std::size_t k = 0; k < list.size(); ++k)
    if (list[k]->type.spec.name == name) slot = int(k);
  if (slot < 0 && int(list.size()) >= kSlots)
    throw Error("too many Python node types in one process (" + std::to_string(kSlots) + ")");
  NodeType type = node_type(name, description, inputs, outputs, flags, source_hash,
                            slot < 0 ? int(list.size()) : slot);
  if (slot < 0) {
    list.push_back(std::make_unique<PythonNode>());
    slot = int(list.size()) - 1;
  }
  PythonNode& node = *list[std::size_t(slot)];
  node.type = std::move(type);
  node.function = std::move(function);
  node.module = module;
  node.wants_context = wants_context;
  for (Registry* r : registries()) add_to(*r, node.type);
}

}  // namespace

ActiveRun::ActiveRun() { ++g_active_runs; }
ActiveRun::~ActiveRun() { --g_active_runs; }

void interrupt_python_bodies() {
  std::lock_guard lock(bodies().mutex);
  for (RunningBody* b : bodies().running)
    if (!b->interrupted) {
      b->interrupted = true;
      PyThreadState_SetAsyncExc(b->ident, PyExc_KeyboardInterrupt);
    }
}

void register_python_nodes(Registry& registry) {
  registries().push_back(&registry);
  for (const auto& n : nodes()) add_to(registry, n->type);
}

void provide_python_nodes(Registry& registry, const std::string& type) {
  py::gil_scoped_acquire gil;
  try {
    py::module_::import("loom._python_nodes").attr("import_node_module")(type);
  } catch (py::error_already_set& e) {
    throw Error("Python node type \"" + type + "\": " + python_error_text(e));
  }
  for (const auto& n : nodes())
    if (type.rfind("py." + n->module + ".", 0) == 0 && !registry.find(n->type.spec.name))
      registry.add(n->type, "python");
}

void bind_python_nodes(py::module_& m) {
  py::class_<PyContext, std::shared_ptr<PyContext>>(m, "Context",
                                                     "What a Python node body may ask of the engine while it runs.")
      .def_property_readonly("node_id", [](const PyContext& c) { return c.get().node_id(); })
      .def_property_readonly("seed", [](const PyContext& c) { return c.get().seed(); },
                             "seeded from the graph seed and the node id")
      .def_property_readonly("frame", [](const PyContext& c) { return c.get().time().frame; })
      .def_property_readonly("seconds", [](const PyContext& c) { return c.get().time().seconds(); })
      .def("progress", [](const PyContext& c, double done, double total, const std::string& label) {
             c.get().progress(done, total, label);
           }, py::arg("done"), py::arg("total"), py::arg("label") = "")
      .def("cancelled", [](const PyContext& c) { return c.get().cancelled(); },
           "True once the run is cancelled (Ctrl-C): return or raise soon")
      .def("warn", [](const PyContext& c, std::string text) { c.get().warn(std::move(text)); })
      .def("log", [](const PyContext& c, std::string text) { c.get().log(std::move(text)); });
  m.def("declare_node", &declare_node);
  m.def("python_node_types", [] {
    std::vector<std::string> names;
    for (const auto& n : nodes()) names.push_back(n->type.spec.name);
    return names;
  });
}

}  // namespace loom::python
