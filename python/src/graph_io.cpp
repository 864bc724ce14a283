// Graphs between Python and the engine: a Python graph is the same JSON
// document a graph file holds (as the editor keeps it), plus the in-memory
// values given to inputs (held_value.hpp). Loading and saving go through the
// engine's parser and writer, so files match the runner's and the editor's.
#include "graph_io.hpp"

#include <fstream>
#include <sstream>

#include <pybind11/stl.h>
#include "loom/atomic_file.hpp"
#include "loom/input_declaration.hpp"

#include "loom/suggest.hpp"
#include "values.hpp"
#include "world.hpp"

namespace loom::python {

namespace {

// The document as the file holds it (fields the engine does not read, such
// as "description" and "ui", kept), after the engine's parser accepted it.
py::tuple load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw GraphError(path, {{"", "cannot open the file"}});
  std::stringstream text;
  text << in.rdbuf();
  Graph g = parse_graph_text(text.str(), path);
  json doc = json::parse(text.str());
  return py::make_tuple(from_json(doc), std::filesystem::absolute(path).string());
}

// Writes the file as the editor does: the document with one space of
// indent, written then renamed.
void save(const py::dict& doc, const std::string& path) {
  const json j = to_json(doc);
  parse_graph(j, path);
  write_file_atomic(path, j.dump(1) + "\n");
}

py::object describe(const std::string& type) { return from_json(describe_node_type(world().type(type))); }

// Every node type of every plugin (all plugins load), by name.
py::dict describe_all() {
  World& w = world();
  std::lock_guard<std::recursive_mutex> lock(w.mutex);
  w.loader.load_all();
  py::dict d;
  for (const NodeType* t : w.registry.all())
    if (t->spec.name != "python.HeldValue") d[py::str(t->spec.name)] = from_json(describe_node_type(*t));
  return d;
}

std::string near_text(const std::string& name, const std::vector<std::string>& names) {
  const auto near = near_names(name, names);
  if (near.empty()) return "";
  std::string text = "; did you mean ";
  for (std::size_t i = 0; i < near.size(); ++i) text += (i ? " or \"" : "\"") + near[i] + "\"";
  return text + "?";
}

const InputSpec& input_of(const NodeType& t, const std::string& input) {
  if (const InputSpec* s = t.spec.find_input(input)) return *s;
  std::vector<std::string> names;
  for (const auto& i : t.spec.inputs) names.push_back(i.name);
  throw Error(t.spec.name + " has no input \"" + input + "\"" + near_text(input, names));
}

// Checks one input value of a node as add() or assignment gives it: returns
// ("literal", json-ready value) or ("held", Held).
py::tuple check_input(const std::string& type, const std::string& input, const py::object& value) {
  const NodeType& t = world().type(type);
  const InputSpec& s = input_of(t, input);
  if (is_held_value(value, *s.type) || !s.type->literal())
    return py::make_tuple("held", hold(from_python(value, *s.type)));
  json j = to_json(value);
  try {
    if (!is_any(*s.type)) check_literal(s, j);  // type, range and choices, as validation checks a graph file's
  } catch (const Error& e) {
    throw Error(input + ": " + e.what());
  }
  return py::make_tuple("literal", from_json(j));
}

void check_link(const std::string& from_type, const std::string& output, const std::string& to_type,
                const std::string& input) {
  const NodeType& from = world().type(from_type);
  const int o = from.spec.output_index(output);
  if (o < 0) {
    std::vector<std::string> names;
    for (const auto& x : from.spec.outputs) names.push_back(x.name);
    throw Error(from_type + " has no output \"" + output + "\"" + near_text(output, names));
  }
  const InputSpec& s = input_of(world().type(to_type), input);
  const TypeInfo& ot = *from.spec.outputs[std::size_t(o)].type;
  if (!link_compatible(ot, *s.type))
    throw Error("cannot link " + from_type + "." + output + " (" + ot.name + ") to " + to_type + "." + input + " (" +
                s.type->name + ")");
}

}  // namespace

void bind_graph_io(py::module_& m) {
  py::class_<Held>(m, "Held", "An in-memory value given to an input, with its content hash.")
      .def_property_readonly("key", [](const Held& h) { return h.key; })
      .def_property_readonly("value", [](const Held& h) { return to_python(h.value); });
  py::class_<PreparedGraph>(m, "PreparedGraph");
  m.def("load_graph", &load);
  m.def("save_graph", &save);
  m.def("describe_node_type", &describe);
  m.def("describe_node_types", &describe_all);
  m.def("check_input", &check_input);
  m.def("near_names", [](const std::string& name, const std::vector<std::string>& names) {
    return near_names(name, names);
  });
  m.def("check_link", &check_link);
  m.def("prepare", [](const py::dict& doc, const std::string& file, const py::dict& held,
                      const std::vector<std::string>& sets) {
    auto p = std::make_unique<PreparedGraph>();
    p->graph = parse_graph(to_json(doc), file);
    for (const auto& s : sets) set_input(p->graph, s);
    for (const auto& [node, inputs] : held)
      for (const auto& [input, h] : inputs.cast<py::dict>())
        p->held.link(p->graph, node.cast<std::string>(), input.cast<std::string>(), h.cast<const Held&>());
    World& w = world();
    w.load_for(node_types_used(p->graph));
    std::lock_guard<std::recursive_mutex> lock(w.mutex);
    validate_graph(p->graph, w.registry, w.loader.searched_description(), w.loader.known_node_types());
    return p;
  });
}

}  // namespace loom::python
