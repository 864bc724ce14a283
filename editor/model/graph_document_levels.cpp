// GraphDocument's levels: the top graph or the group entered (an inline
// group, a group file opened in the document, a Repeat node's body), the
// path to it, and what the file as a whole uses (group types, the format
// version). Grouping itself is in graph_document_groups.cpp.
#include "graph_document.hpp"

#include "auto_layout.hpp"
#include "group_library.hpp"
#include "json_object.hpp"

#include <set>
#include <utility>

namespace loom::editor {

namespace fs = std::filesystem;

const json& GraphDocument::groups() const { return holds_object(doc_, "groups") ? doc_["groups"] : empty_object(); }

fs::path GraphDocument::dir() const { return file_.empty() ? fs::current_path() : file_.parent_path(); }

namespace {

// The group a node opens: its type, or a Repeat node's body.
std::string group_type_of(const json& node) {
  if (!node.is_object()) return {};
  const json type = node.value("type", json());
  const json named = type == "Repeat" ? node.value("body", json()) : type;
  return named.is_string() ? named.get<std::string>() : std::string();
}

const json& groups_of(const json& root) { return holds_object(root, "groups") ? root["groups"] : empty_object(); }

}  // namespace

// Walks the path from the top graph: an inline group is found in the
// "groups" of the document being walked (the graph or a group file), a
// group file among the files opened by enter().
const json* GraphDocument::level_at(std::size_t depth, LevelScope* scope_out) const {
  const json* level = &doc_;
  LevelScope scope{&doc_, dir(), {}};
  for (std::size_t i = 0; i < depth && i < path_.size(); ++i) {
    if (!holds_object(*level, "nodes") || !(*level)["nodes"].contains(path_[i])) return nullptr;
    const std::string type = group_type_of((*level)["nodes"][path_[i]]);
    const json& groups = groups_of(*scope.root);
    if (groups.contains(type) && groups[type].is_object()) {
      level = &groups[type];
    } else {
      const fs::path* file = group_types_.file_of(type, groups, scope.dir);
      auto open = file ? files_.find(file->string()) : files_.end();
      if (open == files_.end()) return nullptr;
      level = scope.root = &open->second.doc;
      scope.dir = file->parent_path();
      scope.file = *file;
    }
    if (!holds_object(*level, "nodes")) return nullptr;
  }
  if (scope_out) *scope_out = scope;
  return level;
}

const json& GraphDocument::level() const {
  const json* level = level_at(path_.size());
  return level ? *level : doc_;
}

json& GraphDocument::level() { return const_cast<json&>(std::as_const(*this).level()); }

GraphDocument::LevelScope GraphDocument::scope() const {
  LevelScope s{&doc_, dir(), {}};
  if (!level_at(path_.size(), &s)) s = {&doc_, dir(), {}};
  return s;
}

const json& GraphDocument::scope_groups() const { return groups_of(*scope().root); }

json& GraphDocument::scope_root() { return const_cast<json&>(*scope().root); }

fs::path GraphDocument::level_file() const { return scope().file; }

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
  if (!has_node(id) || !is_group_node(id)) return false;
  const LevelScope s = scope();
  const std::string type = group_type_of(node_json(id));
  if (const fs::path* file = group_types_.file_of(type, groups_of(*s.root), s.dir)) open_group_file(*file);
  path_.push_back(id);
  if (!level_at(path_.size())) {
    path_.pop_back();
    return false;
  }
  // Hand-written groups without positions are laid out once, as files are.
  const LevelScope inside = scope();
  place_unplaced_nodes_in(level(), [&](const json& node) { return declaration(node, inside); });
  return true;
}

// A group file is read once per document and then edited in memory; save()
// writes it back when an edit changed it.
void GraphDocument::open_group_file(const fs::path& file) {
  if (files_.count(file.string())) return;
  std::string text;
  GroupFileLevel opened;
  opened.doc = read_json_file(file, text);
  if (!holds_object(opened.doc, "nodes"))
    throw GraphError(file.string(), {{"/nodes", "missing: a group file has a \"nodes\" object"}});
  opened.layout = scan_json_layout(text);
  opened.read_text = text;
  GroupFileLevel& level = files_[file.string()] = std::move(opened);
  // Laid out like the graph when opened; a layout alone is not written back.
  const LevelScope inside{&level.doc, file.parent_path(), file};
  place_unplaced_nodes_in(level.doc, [&](const json& node) { return declaration(node, inside); });
  level.saved = level.doc;
  group_types_.edited();  // its type (and a Repeat's over it) now comes from this JSON
}

void GraphDocument::leave(std::size_t depth) {
  if (depth < path_.size()) path_.resize(depth);
}

std::string GraphDocument::group_name() const {
  if (path_.empty()) return {};
  const json* parent = level_at(path_.size() - 1);
  return parent ? group_type_of((*parent)["nodes"][path_.back()]) : std::string();
}

bool GraphDocument::is_group_node(const std::string& id) const {
  const NodeType* t = has_node(id) ? node_type(id) : nullptr;
  return t && !t->run;
}

bool GraphDocument::is_repeat(const std::string& id) const { return has_node(id) && type_name(id) == "Repeat"; }

std::string GraphDocument::repeat_body(const std::string& id) const {
  return is_repeat(id) ? group_type_of(node_json(id)) : std::string();
}

bool GraphDocument::in_repeat_body() const {
  const json* parent = path_.empty() ? nullptr : level_at(path_.size() - 1);
  return parent && (*parent)["nodes"][path_.back()].value("type", json()) == "Repeat";
}

fs::path GraphDocument::group_file(const std::string& id) const {
  const LevelScope s = scope();
  const fs::path* file = group_types_.file_of(group_type_of(node_json(id)), groups_of(*s.root), s.dir);
  return file ? *file : fs::path();
}

bool GraphDocument::has_interface() const {
  return !path_.empty() || doc_.contains("inputs") || doc_.contains("outputs");
}

json GraphDocument::interface_inputs() const {
  return holds_object(level(), "inputs") ? level()["inputs"] : empty_object();
}

std::vector<std::string> GraphDocument::root_node_ids() const {
  std::vector<std::string> ids;
  for (const auto& [id, node] : doc_["nodes"].items()) ids.push_back(id);
  return ids;  // a json object's keys are sorted
}

std::vector<std::string> GraphDocument::types_used() const {
  std::set<std::string> types;
  auto collect = [&](const json& level) {
    if (!holds_object(level, "nodes")) return;
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
    if (const json* level = level_at(depth)) open.insert(group_type_of((*level)["nodes"][path_[depth]]));
  std::vector<std::string> stack{type};
  std::set<std::string> seen;
  while (!stack.empty()) {
    const std::string name = stack.back();
    stack.pop_back();
    if (open.count(name)) return true;
    const json& groups = scope_groups();
    if (!seen.insert(name).second || !groups.contains(name) || !holds_object(groups[name], "nodes")) continue;
    for (const auto& [id, node] : groups[name]["nodes"].items())
      if (node.is_object() && node.contains("type") && node["type"].is_string()) stack.push_back(node["type"]);
  }
  return false;
}

std::vector<const NodeType*> GraphDocument::group_types() const {
  std::vector<const NodeType*> types;
  for (const auto& [name, group] : scope_groups().items())
    if (const NodeType* t = find_type(name); t && !contains_level(name)) types.push_back(t);
  for (const NodeType* t : group_types_.library()) types.push_back(t);
  return types;
}

}  // namespace loom::editor
