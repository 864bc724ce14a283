#include "group_types.hpp"

#include "loom/builtin_types.hpp"
#include "loom/graph_view.hpp"
#include "loom/input_declaration.hpp"

namespace loom::editor {

namespace fs = std::filesystem;

namespace {

// The type of the inner output an interface output comes from ("from": "NODE.OUTPUT").
const TypeInfo* inner_output_type(const json& entry, const json& nodes, const InnerTypeLookup& inner) {
  const json from = entry.is_object() ? entry.value("from", json()) : json();
  const auto link = from.is_string() ? parse_link(from.get<std::string>()) : std::nullopt;
  if (!link || !nodes.contains(link->node) || !nodes[link->node].is_object()) return &type_of<Any>();
  const json type = nodes[link->node].value("type", json());
  const NodeType* t = type.is_string() ? inner(type.get<std::string>()) : nullptr;
  const int o = t ? t->spec.output_index(link->output) : -1;
  return o < 0 ? &type_of<Any>() : t->spec.outputs[std::size_t(o)].type;
}

}  // namespace

NodeType interface_node_type(const std::string& name, const std::string& origin, const json& definition,
                         const InnerTypeLookup& inner) {
  NodeType t;
  t.spec.name = name;
  t.spec.plugin = origin;
  t.spec.description = definition.value("description", std::string());
  const json nodes = definition.value("nodes", json::object());
  const json inputs = definition.value("inputs", json::object());
  const json outputs = definition.value("outputs", json::object());
  for (const auto& [input, entry] : inputs.items())
    if (entry.is_object()) t.spec.inputs.push_back(input_spec_from_json(input, entry, DeclarationReading::lenient));
  for (const auto& [output, entry] : outputs.items())
    t.spec.outputs.push_back({output, "from " + entry.value("from", std::string()),
                              inner_output_type(entry, nodes, inner)});
  return t;
}

GroupTypes::GroupTypes(const Registry& registry) : registry_(registry) {}

const NodeType* GroupTypes::find(const std::string& type, const json& groups, const fs::path& dir) const {
  if (const NodeType* t = registry_.find(type)) return t;
  if (groups.is_object() && groups.contains(type) && groups[type].is_object()) return inline_type(type, groups, dir);
  if (const fs::path* file = resolved(type, dir)) {
    if (const json* doc = open_ ? open_(*file) : nullptr) return open_file_type(*file, *doc);
    return file_type(*file);
  }
  return nullptr;
}

const fs::path* GroupTypes::file_of(const std::string& type, const json& groups, const fs::path& dir) const {
  if (registry_.find(type) || (groups.is_object() && groups.contains(type))) return nullptr;
  return resolved(type, dir);
}

const NodeType* GroupTypes::repeat(const std::string& body, const json& groups, const fs::path& dir) const {
  const std::string key = dir.string() + "\n" + body;
  if (auto it = repeats_.find(key); it != repeats_.end()) return it->second.get();
  const NodeType* group = is_group(body, groups, dir) ? find(body, groups, dir) : nullptr;
  std::unique_ptr<NodeType> t;
  try {
    if (group) t = std::make_unique<NodeType>(repeat_declaration(*group, body));
  } catch (const Error&) {
    // A body declaring "count": validation says so; the node shows as unknown.
  }
  return (repeats_[key] = std::move(t)).get();
}

const NodeType* GroupTypes::open_file_type(const fs::path& file, const json& doc) const {
  const std::string key = file.string();
  if (auto it = opened_.find(key); it != opened_.end()) return it->second.get();
  if (!resolving_.insert(key).second) return nullptr;
  const json groups = doc.value("groups", json::object());
  auto inner = [&](const std::string& type) { return find(type, groups, file.parent_path()); };
  auto t = std::make_unique<NodeType>(interface_node_type(file.stem().string(), file.string(), doc, inner));
  resolving_.erase(key);
  return (opened_[key] = std::move(t)).get();
}

const fs::path* GroupTypes::resolved(const std::string& type, const fs::path& dir) const {
  const std::string key = dir.string() + "\n" + type;
  auto it = resolved_.find(key);
  if (it == resolved_.end()) {
    const auto file = resolve_group_file(type, dir);
    it = resolved_.emplace(key, file ? fs::weakly_canonical(*file) : fs::path()).first;
  }
  return it->second.empty() ? nullptr : &it->second;
}

bool GroupTypes::is_group(const std::string& type, const json& groups, const fs::path& dir) const {
  const NodeType* t = find(type, groups, dir);
  return t && !t->run;
}

const NodeType* GroupTypes::inline_type(const std::string& name, const json& groups, const fs::path& dir) const {
  if (auto it = inline_.find(name); it != inline_.end()) return it->second.get();
  if (!resolving_.insert("inline:" + name).second) return nullptr;  // uses itself
  auto inner = [&](const std::string& type) { return find(type, groups, dir); };
  auto t = std::make_unique<NodeType>(interface_node_type(name, "group", groups[name], inner));
  resolving_.erase("inline:" + name);
  return (inline_[name] = std::move(t)).get();
}

const NodeType* GroupTypes::file_type(const fs::path& file) const {
  const std::string key = file.string();  // canonical (resolved())
  if (auto it = files_.find(key); it != files_.end()) return it->second.get();
  if (!resolving_.insert(key).second) return nullptr;
  std::unique_ptr<NodeType> t;
  try {
    const json doc = read_group_file(file);
    const json groups = doc.value("groups", json::object());
    auto inner = [&](const std::string& type) { return find(type, groups, file.parent_path()); };
    t = std::make_unique<NodeType>(interface_node_type(file.stem().string(), file.string(), doc, inner));
  } catch (const GraphError&) {
    // Not a group file: the node shows as of an unknown type.
  }
  resolving_.erase(key);
  return (files_[key] = std::move(t)).get();
}

std::vector<const NodeType*> GroupTypes::library() const {
  std::vector<const NodeType*> types;
  if (!library_) library_ = list_library_groups();
  for (const LibraryGroup& g : *library_) {
    if (registry_.find(g.name)) continue;  // a registered type takes the name
    const fs::path file = fs::weakly_canonical(g.file);
    const NodeType* t = file_type(file);
    if (t && (!t->spec.inputs.empty() || !t->spec.outputs.empty())) {  // a group file, not a plain graph
      files_[file.string()]->spec.plugin = "library";
      types.push_back(t);
    }
  }
  return types;
}

void GroupTypes::edited() {
  retired_.clear();
  for (auto* built : {&inline_, &opened_, &repeats_}) {
    for (auto& [name, t] : *built)
      if (t) retired_.push_back(std::move(t));
    built->clear();
  }
}

void GroupTypes::rescan() {
  edited();
  for (auto& [file, t] : files_)
    if (t) retired_.push_back(std::move(t));
  files_.clear();
  resolved_.clear();
  library_.reset();
}

}  // namespace loom::editor
