#include "loom/registry.hpp"

#include "loom/input_declaration.hpp"

namespace loom {

namespace {

// What the engine relies on in a declaration, checked once here rather than at
// every evaluation: names without '.' (links split "ID.OUTPUT" at the last
// '.'), and a simulation's state input and output of one type.
void check_declaration(const NodeSpec& spec, const std::string& plugin) {
  auto bug = [&](const std::string& what) {
    return Error("node type " + spec.name + " of plugin " + plugin + " " + what + " (a bug in the node)");
  };
  for (const InputSpec& in : spec.inputs)
    if (in.name.empty() || in.name.find('.') != std::string::npos)
      throw bug("declares an input named \"" + in.name + "\": names are non-empty and hold no '.'");
  for (const OutputSpec& out : spec.outputs)
    if (out.name.empty() || out.name.find('.') != std::string::npos)
      throw bug("declares an output named \"" + out.name + "\": names are non-empty and hold no '.'");
  if (!spec.simulation()) return;
  const int in = spec.input_index(spec.state_input), out = spec.output_index(spec.state_output);
  if (in < 0 || out < 0 ||
      spec.inputs[static_cast<std::size_t>(in)].type->storage != spec.outputs[static_cast<std::size_t>(out)].type->storage)
    throw bug("declares a simulation state \"" + spec.state_input + "\" -> \"" + spec.state_output +
              "\" without that input and output of one type");
}

}  // namespace

void Registry::add(NodeType type, const std::string& plugin) {
  if (type.spec.name.empty()) throw Error("plugin " + plugin + " registered a node without a name");
  check_declaration(type.spec, plugin);
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
    json j = input_spec_to_json(in);  // with every key of the listing present
    j["name"] = in.name;
    j["description"] = in.description;
    j["default"] = in.default_value;
    j["required"] = in.required();
    if (in.lazy) j["lazy"] = true;
    if (in.role == InputRole::input_file) j["role"] = "input_file";
    if (in.role == InputRole::output_file) j["role"] = "output_file";
    inputs.push_back(std::move(j));
  }
  json outputs = json::array();
  for (const OutputSpec& o : s.outputs)
    outputs.push_back({{"name", o.name}, {"type", o.type->name}, {"description", o.description}});
  json flags = json::array();
  if (s.sink) flags.push_back("sink");
  if (s.sequence) flags.push_back("sequence");
  if (s.pixel_independent) flags.push_back("pixel_independent");
  if (s.sample_passes) flags.push_back("sample_passes");
  if (s.nondeterministic) flags.push_back("nondeterministic");
  if (s.time_dependent) flags.push_back("time_dependent");
  if (s.simulation()) flags.push_back("simulation");
  json j = {{"plugin", s.plugin}, {"version", s.version}, {"description", s.description},
            {"inputs", inputs},   {"outputs", outputs},   {"flags", flags}};
  if (s.simulation()) j["state"] = {{"input", s.state_input}, {"output", s.state_output}};
  return j;
}

}  // namespace loom
