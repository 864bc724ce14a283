// A group interface input's declaration, read into the InputSpec a C++ node
// declares: the same keys as `loom nodes --json` prints for an input.
#include "graph_groups.hpp"
#include "input_binding.hpp"
#include "repeat.hpp"

namespace loom::detail {

namespace {

void read_range(InputSpec& s, const json& d) {
  for (const char* key : {"min", "max"}) {
    if (!d.contains(key)) continue;
    if (!d[key].is_number()) throw Error(std::string("\"") + key + "\": expected a number, got " + describe_json(d[key]));
    (std::string(key) == "min" ? s.min : s.max) = d[key].get<double>();
  }
}

void read_choices(InputSpec& s, const json& d) {
  if (!d.contains("choices")) return;
  if (!d["choices"].is_array() || d["choices"].empty()) throw Error("\"choices\": expected a list of strings");
  for (const json& c : d["choices"]) {
    if (!c.is_string()) throw Error("\"choices\": expected strings, got " + describe_json(c));
    s.choices.push_back(c);
  }
}

}  // namespace

InputSpec interface_input_spec(const std::string& name, const json& d) {
  InputSpec s;
  s.name = name;
  const std::string type = d.value("type", std::string());
  s.type = find_type(type);
  if (!s.type) throw Error("\"type\": unknown type \"" + type + "\"");
  if (d.contains("description")) {
    if (!d["description"].is_string()) throw Error("\"description\": expected a string");
    s.description = d["description"];
  }
  if (d.contains("optional")) {
    if (!d["optional"].is_boolean()) throw Error("\"optional\": expected true or false");
    s.optional = d["optional"];
  }
  read_range(s, d);
  read_choices(s, d);
  if (type == "Enum" && s.choices.empty()) throw Error("an Enum input needs \"choices\"");
  if (d.contains("default")) {
    try {
      literal_value(s, d["default"]);
    } catch (const Error& e) {
      throw Error(std::string("\"default\": ") + e.what());
    }
    s.default_value = d["default"];
  }
  return s;
}

const NodeType* node_type_of(const GraphNode& node, const Registry& registry) {
  if (!node.repeat) return registry.find(node.type);
  try {
    return &repeat_node_type(*node.repeat, registry);
  } catch (const Error&) {  // an invalid body: validation reports why (repeat_node_type)
    return nullptr;
  }
}

}  // namespace loom::detail
