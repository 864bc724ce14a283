// GraphDocument's group edits: group (inline or into a file), ungroup,
// promote; each one undo step.
#include "graph_document.hpp"

#include "auto_layout.hpp"
#include "group_edit.hpp"
#include "input_link.hpp"
#include "json_object.hpp"

#include <algorithm>
#include <set>

#include "loom/atomic_file.hpp"

namespace loom::editor {

namespace fs = std::filesystem;

namespace {

CanvasPoint centre_of(const GraphDocument& doc, const std::vector<std::string>& ids) {
  CanvasPoint c;
  for (const auto& id : ids) {
    c.x += doc.position(id).x / double(ids.size());
    c.y += doc.position(id).y / double(ids.size());
  }
  return c;
}

}  // namespace

// The group node replacing `ids`: its inputs linked as the interface needs,
// the consumers of the group's outputs rewired to it.
std::string GraphDocument::add_group_node(const std::string& type, const std::vector<std::string>& ids,
                                          const json& inputs) {
  const CanvasPoint centre = centre_of(*this, ids);
  for (const auto& id : ids) nodes().erase(id);
  // At the free spot nearest the selection's centre, never on another node.
  std::vector<CanvasRect> taken;
  for (const auto& other : node_ids())
    taken.push_back({position(other).x, position(other).y, kNodeWidth, node_height(node_type(other))});
  const CanvasPoint at = free_spot(taken, centre, kNodeWidth, node_height(find_type(type)));
  const std::string id = unique_id(type);
  nodes()[id] = {{"type", type}, {"ui", {{"pos", {at.x, at.y}}}}};
  if (!inputs.empty()) nodes()[id]["inputs"] = inputs;
  return id;
}

namespace {

Grouping grouping_of(const GraphDocument& doc, const json& nodes, const std::vector<std::string>& ids) {
  std::set<std::string> chosen;
  for (const auto& id : ids)
    if (doc.has_node(id)) chosen.insert(id);
  if (chosen.empty()) throw Error("nothing to group: select nodes first");
  return make_grouping(nodes, chosen, [&](const std::string& id) { return doc.node_type(id); });
}

void rewire(json& nodes, const std::map<std::pair<std::string, std::string>, std::string>& consumers,
            const std::string& group_node) {
  for (const auto& [consumer, output] : consumers)
    nodes[consumer.first]["inputs"][consumer.second] = {{"from", link_text(group_node, output)}};
}

}  // namespace

std::string GraphDocument::group(const std::vector<std::string>& ids, const std::string& name) {
  const Grouping g = grouping_of(*this, nodes(), ids);
  const std::string type = name.empty()
                               ? unique_name("Group",
                                             [&](const std::string& n) {
                                               return scope_groups().contains(n) || registry_.find(n) != nullptr;
                                             })
                               : name;
  if (registry_.find(type) || scope_groups().contains(type))
    throw Error("cannot name the group \"" + type + "\": a node type or group of that name exists");
  begin_edit("group " + std::to_string(g.definition["nodes"].size()) + " nodes as " + type);
  scope_root()["groups"][type] = g.definition;
  const std::string id = add_group_node(type, ids, g.instance_inputs);
  rewire(nodes(), g.consumers, id);
  return id;
}

std::string GraphDocument::group_to_file(const std::vector<std::string>& ids, const fs::path& file) {
  const Grouping g = grouping_of(*this, nodes(), ids);
  json contents = {{"loom", 2}};
  contents.update(g.definition);
  // Inline groups the selection uses go with it: the file must stand alone.
  json used = json::object();
  for (const auto& [id, node] : g.definition["nodes"].items())
    if (const std::string t = node.value("type", std::string()); scope_groups().contains(t))
      used[t] = scope_groups()[t];
  if (!used.empty()) contents["groups"] = used;
  write_file_atomic(file, write_json(contents, JsonLayout{}));
  const fs::path absolute = fs::absolute(file);
  const std::string type = absolute.lexically_relative(fs::absolute(scope().dir)).generic_string();
  begin_edit("group " + std::to_string(g.definition["nodes"].size()) + " nodes into " + file.filename().string());
  group_types_.rescan();
  const std::string id = add_group_node(type, ids, g.instance_inputs);
  rewire(nodes(), g.consumers, id);
  return id;
}

std::vector<std::string> GraphDocument::ungroup(const std::string& id) {
  const std::string type = type_name(id);
  json definition;
  if (scope_groups().contains(type))
    definition = scope_groups()[type];
  else if (const fs::path file = group_file(id); !file.empty())
    definition = files_.count(file.string()) ? files_.at(file.string()).doc : read_group_file(file);
  else
    throw Error(id + " is not a group node");
  // A group file's own inline groups come along (the same name must mean the same group).
  const json file_groups =
      holds_object(definition, "groups") && !scope_groups().contains(type) ? definition["groups"] : empty_object();
  for (const auto& [name, group] : file_groups.items())
    if (registry_.find(name) || (scope_groups().contains(name) && scope_groups()[name] != group))
      throw Error("cannot ungroup " + id + ": its file's group \"" + name + "\" differs from this graph's");
  const Ungrouping u = dissolve_group(id, node_json(id), definition, [&](const std::string& n) { return has_node(n); });
  begin_edit("ungroup " + id);
  for (const auto& [name, group] : file_groups.items()) scope_root()["groups"][name] = group;
  const CanvasPoint at = position(id);
  nodes().erase(id);
  std::vector<std::string> added;
  for (const auto& [new_id, node] : u.nodes.items()) {
    nodes()[new_id] = node;
    added.push_back(new_id);
  }
  const CanvasPoint centre = centre_of(*this, added);
  for (const auto& new_id : added) {
    const CanvasPoint p = position(new_id);
    nodes()[new_id]["ui"]["pos"] = {p.x + at.x - centre.x, p.y + at.y - centre.y};
  }
  for (auto& [other, node] : nodes().items()) {
    if (!node.is_object() || !node.contains("inputs")) continue;
    for (auto& [input, value] : node["inputs"].items())
      if (auto l = input_link(value); l && l->node == id && u.outputs.count(l->output))
        value = {{"from", u.outputs.at(l->output)}};
  }
  drop_unused_groups();
  return added;
}

// Inline groups that no node of the file uses any more.
void GraphDocument::drop_unused_groups() {
  if (!scope().file.empty()) return;  // a group file's own groups are left as they are
  for (bool dropped = true; dropped && doc_.contains("groups");) {
    const std::vector<std::string> used = types_used();
    std::vector<std::string> unused;
    for (const auto& [name, group] : doc_["groups"].items())
      if (!std::binary_search(used.begin(), used.end(), name)) unused.push_back(name);
    for (const auto& name : unused) doc_["groups"].erase(name);
    if (doc_["groups"].empty()) doc_.erase("groups");
    dropped = !unused.empty();
  }
}

std::string GraphDocument::promote(const std::string& id, const std::string& input) {
  if (!has_interface()) throw Error("promote works inside a group: enter one first");
  const NodeType* t = node_type(id);
  const InputSpec* declared = t ? t->spec.find_input(input) : nullptr;
  if (!declared) throw Error(id + " has no input \"" + input + "\"");
  if (link(id, input)) throw Error(link_text(id, input) + " is linked: only an unlinked input can be promoted");
  if (!promoted_as(id, input).empty()) throw Error(link_text(id, input) + " is already an input of the group");
  begin_edit("promote " + link_text(id, input));
  return promote_input(level(), id, input, *declared);
}

std::string GraphDocument::exported_as(const std::string& id, const std::string& output) const {
  const json& level = this->level();
  if (!holds_object(level, "outputs")) return {};
  for (const auto& [name, entry] : level["outputs"].items())
    if (entry.is_object() && entry.value("from", std::string()) == link_text(id, output)) return name;
  return {};
}

std::string GraphDocument::promoted_as(const std::string& id, const std::string& input) const {
  return has_interface() ? interface_input_of(level(), id, input) : std::string();
}

const json* GraphDocument::instance_node() const {
  const json* parent = path_.empty() ? nullptr : level_at(path_.size() - 1);
  return parent ? &(*parent)["nodes"][path_.back()] : nullptr;
}

json& GraphDocument::instance_inputs() {
  const json* node = instance_node();
  if (!node) throw Error("no group entered: an instance's values are given inside one");
  return const_cast<json&>(*node)["inputs"];
}

json GraphDocument::instance_literal(const std::string& name) const {
  const json* node = instance_node();
  if (!node || !holds_object(*node, "inputs") || !(*node)["inputs"].contains(name)) return nullptr;
  const json& v = (*node)["inputs"][name];
  return input_link(v) ? json() : v;
}

std::optional<Link> GraphDocument::instance_link(const std::string& name) const {
  const json* node = instance_node();
  if (!node || !holds_object(*node, "inputs") || !(*node)["inputs"].contains(name)) return std::nullopt;
  return input_link((*node)["inputs"][name]);
}

void GraphDocument::set_instance_input(const std::string& name, json value, const std::string& merge_key) {
  if (instance_literal(name) == value) return;
  begin_edit("set " + link_text(instance_id(), name), merge_key);
  instance_inputs()[name] = std::move(value);
}

void GraphDocument::reset_instance_input(const std::string& name) {
  if (instance_literal(name).is_null() && !instance_link(name)) return;
  begin_edit("reset " + link_text(instance_id(), name));
  json& inputs = instance_inputs();
  inputs.erase(name);
  if (inputs.empty()) const_cast<json&>(*instance_node()).erase("inputs");
}

std::string GraphDocument::set_for_instance(const std::string& id, const std::string& input, json value) {
  if (path_.empty()) throw Error("enter a group first: an instance's values are given inside one");
  std::string name = promoted_as(id, input);
  if (name.empty()) {
    const NodeType* t = node_type(id);
    const InputSpec* declared = t ? t->spec.find_input(input) : nullptr;
    if (!declared) throw Error(id + " has no input \"" + input + "\"");
    if (link(id, input)) throw Error(link_text(id, input) + " is linked inside the group: it takes no value");
    begin_edit("set " + link_text(id, input) + " for " + instance_id() + " only");
    name = promote_input(level(), id, input, *declared);
  } else {
    begin_edit("set " + link_text(instance_id(), name));
  }
  instance_inputs()[name] = std::move(value);
  return name;
}

}  // namespace loom::editor
