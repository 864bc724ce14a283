#include "loom/registry.hpp"

namespace loom {

void Registry::add(NodeType type, const std::string& plugin) {
  if (type.spec.name.empty()) throw Error("plugin " + plugin + " registered a node without a name");
  if (auto it = types_.find(type.spec.name); it != types_.end())
    throw Error("node type " + type.spec.name + " is registered twice: by plugin " +
                it->second->spec.plugin + " and by plugin " + plugin);
  type.spec.plugin = plugin;
  std::string name = type.spec.name;
  types_.emplace(std::move(name), std::make_unique<NodeType>(std::move(type)));
}

const NodeType* Registry::find(std::string_view name) const {
  auto it = types_.find(name);
  return it == types_.end() ? nullptr : it->second.get();
}

std::vector<const NodeType*> Registry::all() const {
  std::vector<const NodeType*> out;
  for (const auto& [name, t] : types_) out.push_back(t.get());
  return out;
}

json describe_node_type(const NodeType& type) {
  const NodeSpec& s = type.spec;
  json inputs = json::array();
  for (const InputSpec& in : s.inputs) {
    json j = {{"name", in.name}, {"type", in.type->name}, {"description", in.description}};
    j["default"] = in.default_value;
    j["required"] = in.required();
    if (in.optional) j["optional"] = true;
    if (in.lazy) j["lazy"] = true;
    if (in.min) j["min"] = *in.min;
    if (in.max) j["max"] = *in.max;
    if (!in.choices.empty()) j["choices"] = in.choices;
    if (in.role == InputRole::input_file) j["role"] = "input_file";
    if (in.role == InputRole::output_file) j["role"] = "output_file";
    inputs.push_back(std::move(j));
  }
  json outputs = json::array();
  for (const OutputSpec& o : s.outputs)
    outputs.push_back({{"name", o.name}, {"type", o.type->name}, {"description", o.description}});
  json flags = json::array();
  if (s.sink) flags.push_back("sink");
  if (s.nondeterministic) flags.push_back("nondeterministic");
  if (s.time_dependent) flags.push_back("time_dependent");
  if (s.simulation()) flags.push_back("simulation");
  json j = {{"plugin", s.plugin}, {"version", s.version}, {"description", s.description},
            {"inputs", inputs},   {"outputs", outputs},   {"flags", flags}};
  if (s.simulation()) j["state"] = {{"input", s.state_input}, {"output", s.state_output}};
  return j;
}

}  // namespace loom
