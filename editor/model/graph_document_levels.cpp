// GraphDocument's levels: the top graph or the inline group entered, the
// path to it, and what the file as a whole uses (group types, the format
// version). Grouping itself is in graph_document_groups.cpp.
#include "graph_document.hpp"

#include "auto_layout.hpp"
#include "json_object.hpp"

#include <set>
#include <utility>

namespace loom::editor {

namespace fs = std::filesystem;

const json& GraphDocument::groups() const { return is_object_with(doc_, "groups") ? doc_["groups"] : empty_object(); }

fs::path GraphDocument::dir() const { return file_.empty() ? fs::current_path() : file_.parent_path(); }

const json* GraphDocument::level_at(std::size_t depth) const {
  const json* level = &doc_;
  for (std::size_t i = 0; i < depth && i < path_.size(); ++i) {
    if (!is_object_with(*level, "nodes") || !(*level)["nodes"].contains(path_[i])) return nullptr;
    const json& node = (*level)["nodes"][path_[i]];
    const json type = node.is_object() ? node.value("type", json()) : json();
    if (!type.is_string() || !is_object_with(doc_, "groups") || !doc_["groups"].contains(type.get<std::string>()))
      return nullptr;
    level = &doc_["groups"][type.get<std::string>()];
    if (!is_object_with(*level, "nodes")) return nullptr;
  }
  return level;
}

const json& GraphDocument::level() const {
  const json* level = level_at(path_.size());
  return level ? *level : doc_;
}

json& GraphDocument::level() { return const_cast<json&>(std::as_const(*this).level()); }

// After undo or redo the group entered may be gone: edit the deepest level left.
void GraphDocument::trim_path() {
  std::size_t depth = 0;
  while (depth < path_.size() && level_at(depth + 1)) ++depth;
  path_.resize(depth);
}

std::string GraphDocument::path_prefix() const {
  std::string prefix;
  for (const auto& id : path_) prefix += id + ".";
  return prefix;
}

bool GraphDocument::enter(const std::string& id) {
  if (!has_node(id) || !groups().contains(type_name(id))) return false;
  path_.push_back(id);
  if (!level_at(path_.size())) {
    path_.pop_back();
    return false;
  }
  // Hand-written groups without positions are laid out once, as files are.
  place_unplaced_nodes_in(level(), registry_);
  return true;
}

void GraphDocument::leave(std::size_t depth) {
  if (depth < path_.size()) path_.resize(depth);
}

std::string GraphDocument::group_name() const {
  if (path_.empty()) return {};
  const json* parent = level_at(path_.size() - 1);
  return parent ? (*parent)["nodes"][path_.back()].value("type", std::string()) : std::string();
}

bool GraphDocument::is_group_node(const std::string& id) const {
  const NodeType* t = has_node(id) ? node_type(id) : nullptr;
  return t && !t->run;
}

fs::path GraphDocument::group_file(const std::string& id) const {
  const std::string type = type_name(id);
  if (registry_.find(type) || groups().contains(type)) return {};
  return resolve_group_file(type, dir()).value_or(fs::path());
}

bool GraphDocument::has_interface() const {
  return !path_.empty() || doc_.contains("inputs") || doc_.contains("outputs");
}

json GraphDocument::interface_inputs() const {
  return is_object_with(level(), "inputs") ? level()["inputs"] : empty_object();
}

std::vector<std::string> GraphDocument::root_node_ids() const {
  std::vector<std::string> ids;
  for (const auto& [id, node] : doc_["nodes"].items()) ids.push_back(id);
  return ids;  // a json object's keys are sorted
}

std::vector<std::string> GraphDocument::types_used() const {
  std::set<std::string> types;
  auto collect = [&](const json& level) {
    if (!is_object_with(level, "nodes")) return;
    for (const auto& [id, node] : level["nodes"].items())
      if (node.is_object() && node.contains("type") && node["type"].is_string()) types.insert(node["type"]);
  };
  collect(doc_);
  for (const auto& [name, group] : groups().items()) collect(group);
  return {types.begin(), types.end()};
}

int GraphDocument::format_version() const {
  if (!groups().empty() || doc_.contains("inputs") || doc_.contains("outputs")) return 2;
  for (const auto& type : types_used())
    if (type == "Repeat" || (!registry_.find(type) && group_types_.is_group(type, groups(), dir()))) return 2;
  return kGraphFormatVersion;
}

// Whether inline group `type` is, or uses, a group being edited (on the path):
// a node of it here would make a group that contains itself.
bool GraphDocument::contains_level(const std::string& type) const {
  std::set<std::string> open;
  for (std::size_t depth = 0; depth < path_.size(); ++depth)
    if (const json* level = level_at(depth)) open.insert((*level)["nodes"][path_[depth]].value("type", std::string()));
  std::vector<std::string> stack{type};
  std::set<std::string> seen;
  while (!stack.empty()) {
    const std::string name = stack.back();
    stack.pop_back();
    if (open.count(name)) return true;
    if (!seen.insert(name).second || !groups().contains(name) || !is_object_with(groups()[name], "nodes")) continue;
    for (const auto& [id, node] : groups()[name]["nodes"].items())
      if (node.is_object() && node.contains("type") && node["type"].is_string()) stack.push_back(node["type"]);
  }
  return false;
}

std::vector<const NodeType*> GraphDocument::group_types() const {
  std::vector<const NodeType*> types;
  for (const auto& [name, group] : groups().items())
    if (const NodeType* t = find_type(name); t && !contains_level(name)) types.push_back(t);
  for (const NodeType* t : group_types_.library()) types.push_back(t);
  return types;
}

}  // namespace loom::editor
