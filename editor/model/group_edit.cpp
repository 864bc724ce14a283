#include "group_edit.hpp"

#include "input_link.hpp"

#include <vector>

#include "loom/builtin_types.hpp"
#include "loom/input_declaration.hpp"

namespace loom::editor {

namespace {

// The declared type of an inner input fed from outside; an Any input takes
// the type of the output feeding it, when known.
std::string crossing_type(const NodeType* inner, const std::string& input, const NodeType* outer,
                          const std::string& output) {
  const InputSpec* in = inner ? inner->spec.find_input(input) : nullptr;
  if (in && !is_any(*in->type)) return in->type->name;
  const int o = outer ? outer->spec.output_index(output) : -1;
  return o >= 0 ? outer->spec.outputs[std::size_t(o)].type->name : std::string("Any");
}

bool within(const json& object, const std::string& key) { return object.is_object() && object.contains(key); }

void add_interface_inputs(Grouping& g, const std::set<std::string>& chosen,
                          const NodeTypeOf& type_of_node) {
  std::map<std::string, std::string> by_source;  // "OUTER.OUTPUT" -> interface input
  json& inputs = g.definition["inputs"];
  for (const std::string& id : chosen) {
    json& inner = g.definition["nodes"][id];
    if (!within(inner, "inputs")) continue;
    std::vector<std::string> fed;
    for (const auto& [input, value] : inner["inputs"].items()) {
      const auto link = input_link(value);
      if (!link || chosen.count(link->node)) continue;
      const std::string source = link_text(*link);
      const std::string type = crossing_type(type_of_node(id), input, type_of_node(link->node), link->output);
      auto known = by_source.find(source);
      if (known == by_source.end() || inputs[known->second]["type"] != type) {
        const std::string base = within(inputs, input) ? id + "_" + input : input;
        const std::string name = unique_name(base, [&](const std::string& n) { return within(inputs, n); });
        inputs[name] = {{"type", type}, {"to", json::array()}};
        g.instance_inputs[name] = {{"from", source}};
        known = by_source.insert_or_assign(source, name).first;
      }
      inputs[known->second]["to"].push_back(link_text(id, input));
      fed.push_back(input);
    }
    for (const std::string& input : fed) inner["inputs"].erase(input);
    if (inner["inputs"].empty()) inner.erase("inputs");
  }
}

// The inner outputs read outside the selection, "NODE.OUTPUT", in order.
std::vector<Link> outputs_read_outside(const json& nodes, const std::set<std::string>& chosen) {
  std::vector<Link> read;
  std::set<std::string> seen;
  for (const auto& [id, node] : nodes.items()) {
    if (chosen.count(id) || !within(node, "inputs")) continue;
    for (const auto& [input, value] : node["inputs"].items())
      if (const auto link = input_link(value); link && chosen.count(link->node))
        if (seen.insert(link_text(*link)).second) read.push_back(*link);
  }
  return read;
}

void add_interface_outputs(Grouping& g, const json& nodes, const std::set<std::string>& chosen) {
  // An output keeps its name unless two inner nodes' outputs of that name leave the group.
  std::map<std::string, int> uses;
  for (const Link& l : outputs_read_outside(nodes, chosen)) ++uses[l.output];
  std::map<std::string, std::string> by_source;  // "INNER.OUTPUT" -> interface output
  json& outputs = g.definition["outputs"];
  for (const auto& [id, node] : nodes.items()) {
    if (chosen.count(id) || !within(node, "inputs")) continue;
    for (const auto& [input, value] : node["inputs"].items()) {
      const auto link = input_link(value);
      if (!link || !chosen.count(link->node)) continue;
      const std::string source = link_text(*link);
      auto known = by_source.find(source);
      if (known == by_source.end()) {
        const std::string base = uses[link->output] > 1 ? link->node + "_" + link->output : link->output;
        const std::string name = unique_name(base, [&](const std::string& n) { return within(outputs, n); });
        outputs[name] = {{"from", source}};
        known = by_source.emplace(source, name).first;
      }
      g.consumers[{id, input}] = known->second;
    }
  }
}

}  // namespace

std::string unique_name(const std::string& base, const std::function<bool(const std::string&)>& taken) {
  if (!taken(base)) return base;
  for (int i = 2;; ++i)
    if (!taken(base + std::to_string(i))) return base + std::to_string(i);
}

Grouping make_grouping(const json& nodes, const std::set<std::string>& chosen, const NodeTypeOf& type_of_node) {
  Grouping g;
  g.definition = {{"inputs", json::object()}, {"outputs", json::object()}, {"nodes", json::object()}};
  g.instance_inputs = json::object();
  for (const std::string& id : chosen) g.definition["nodes"][id] = nodes[id];
  add_interface_inputs(g, chosen, type_of_node);
  add_interface_outputs(g, nodes, chosen);
  return g;
}

Ungrouping dissolve_group(const std::string& id, const json& instance, const json& definition,
                          const std::function<bool(const std::string&)>& taken) {
  Ungrouping u;
  u.nodes = json::object();
  const json& inner = definition["nodes"];
  for (const auto& [inner_id, node] : inner.items()) {
    const std::string fresh =
        unique_name(id + "_" + inner_id, [&](const std::string& n) { return taken(n) || u.nodes.contains(n); });
    u.renamed[inner_id] = fresh;
    u.nodes[fresh] = node;
  }
  for (auto& [new_id, node] : u.nodes.items()) {
    if (!within(node, "inputs")) continue;
    for (auto& [input, value] : node["inputs"].items())
      if (auto link = input_link(value); link && u.renamed.count(link->node))
        value = {{"from", link_text(u.renamed[link->node], link->output)}};
  }
  const json given = instance.value("inputs", json::object());
  const json interface_inputs = definition.value("inputs", json::object());
  const json interface_outputs = definition.value("outputs", json::object());
  for (const auto& [name, entry] : interface_inputs.items()) {
    const json value = given.contains(name) ? given[name] : entry.value("default", json());
    if (value.is_null()) continue;
    const json targets = entry.value("to", json::array());
    for (const json& target : targets) {
      const auto bound = target.is_string() ? parse_link(target.get<std::string>()) : std::nullopt;
      if (bound && u.renamed.count(bound->node)) u.nodes[u.renamed[bound->node]]["inputs"][bound->output] = value;
    }
  }
  for (const auto& [name, entry] : interface_outputs.items()) {
    const auto from = parse_link(entry.value("from", std::string()));
    if (from && u.renamed.count(from->node)) u.outputs[name] = link_text(u.renamed[from->node], from->output);
  }
  return u;
}

std::string promote_input(json& group, const std::string& node, const std::string& input,
                          const InputSpec& declared) {
  json& inputs = group["inputs"];
  if (!inputs.is_object()) inputs = json::object();
  const std::string name = unique_name(input, [&](const std::string& n) { return inputs.contains(n); });
  json& inner = group["nodes"][node];
  const bool literal = within(inner, "inputs") && inner["inputs"].contains(input);
  InputSpec promoted = declared;  // the node's value becomes the interface's default
  if (literal) promoted.default_value = inner["inputs"][input];
  json entry = input_spec_to_json(promoted);
  entry["to"] = {link_text(node, input)};
  inputs[name] = std::move(entry);
  if (literal) {
    inner["inputs"].erase(input);
    if (inner["inputs"].empty()) inner.erase("inputs");
  }
  return name;
}

std::string interface_input_of(const json& group, const std::string& node, const std::string& input) {
  if (!within(group, "inputs") || !group["inputs"].is_object()) return {};
  const std::string target = link_text(node, input);
  for (const auto& [name, entry] : group["inputs"].items())
    if (entry.is_object() && entry.contains("to") && entry["to"].is_array())
      for (const json& t : entry["to"])
        if (t == target) return name;
  return {};
}

}  // namespace loom::editor
