#include "graph_document.hpp"

#include "auto_layout.hpp"
#include "group_library.hpp"
#include "input_link.hpp"
#include "json_object.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "loom/atomic_file.hpp"

namespace loom::editor {

namespace {

json empty_graph() { return json{{"loom", kGraphFormatVersion}, {"nodes", json::object()}}; }

// "ImageWarp" -> "image_warp".
std::string snake_case(const std::string& type) {
  std::string id;
  for (std::size_t i = 0; i < type.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(type[i]);
    if (std::isupper(c) && i > 0 && !std::isupper(static_cast<unsigned char>(type[i - 1]))) id += '_';
    id += std::isalnum(c) ? static_cast<char>(std::tolower(c)) : '_';
  }
  return id.empty() ? "node" : id;
}

}  // namespace

GraphDocument::GraphDocument(const Registry& registry)
    : registry_(registry), doc_(empty_graph()), group_types_(registry) {
  // A group file being edited declares what its JSON says now, not its file.
  group_types_.set_open_files([this](const std::filesystem::path& file) -> const json* {
    auto it = files_.find(file.string());
    return it == files_.end() ? nullptr : &it->second.doc;
  });
}

void GraphDocument::clear() {
  doc_ = empty_graph();
  layout_ = {};
  read_text_.reset();
  file_.clear();
  path_.clear();
  files_.clear();
  group_types_.rescan();
  history_.clear();
  saved_state_ = history_.state();
  ++revision_;
}

void GraphDocument::load(const std::filesystem::path& file) {
  std::string text;
  const json doc = read_json_file(file, text);
  load_json(doc, std::filesystem::absolute(file));
  layout_ = scan_json_layout(text);
  read_text_ = text;
}

void GraphDocument::load_json(const json& document, const std::filesystem::path& file) {
  check_graph_structure(document, file);  // structure only: a graph with unknown types still opens
  doc_ = document;
  file_ = file;
  layout_ = {};
  read_text_.reset();
  path_.clear();
  files_.clear();
  group_types_.rescan();
  place_unplaced_nodes();
  history_.clear();
  saved_state_ = history_.state();
  ++revision_;
}

std::string GraphDocument::text() const {
  const int version = format_version();
  if (doc_.value("loom", json()) == version) return write_json(doc_, layout_);
  json versioned = doc_;
  versioned["loom"] = version;
  return write_json(versioned, layout_);
}

void GraphDocument::save(const std::filesystem::path& file) {
  const std::string written = text();
  write_file_atomic(file, written);
  save_group_files();
  layout_ = scan_json_layout(written);
  read_text_ = written;
  file_ = std::filesystem::absolute(file);
  saved_state_ = history_.state();
}

void GraphDocument::save_group_files() {
  for (auto& [path, level] : files_) {
    if (level.doc == level.saved) continue;
    const std::string written = write_json(level.doc, level.layout);
    write_file_atomic(path, written);
    level.layout = scan_json_layout(written);
    level.read_text = written;
    level.saved = level.doc;
  }
}

std::vector<std::filesystem::path> GraphDocument::edited_group_files() const {
  std::vector<std::filesystem::path> edited;
  for (const auto& [path, level] : files_)
    if (level.doc != level.saved) edited.emplace_back(path);
  return edited;
}

namespace {

// Whether `file` holds other text than `known` (a missing file holds none:
// saving over it loses nothing).
bool differs_on_disk(const std::filesystem::path& file, const std::string& known) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return false;
  std::stringstream text;
  text << in.rdbuf();
  return text.str() != known;
}

}  // namespace

std::vector<std::filesystem::path> GraphDocument::changed_on_disk() const {
  std::vector<std::filesystem::path> changed;
  if (!file_.empty() && read_text_ && differs_on_disk(file_, *read_text_)) changed.push_back(file_);
  for (const auto& [path, level] : files_)
    if (level.doc != level.saved && differs_on_disk(path, level.read_text)) changed.emplace_back(path);
  return changed;
}

std::vector<std::string> GraphDocument::node_ids() const {
  std::vector<std::string> ids;
  for (const auto& [id, node] : nodes().items()) ids.push_back(id);
  std::sort(ids.begin(), ids.end());
  return ids;
}

bool GraphDocument::has_node(const std::string& id) const { return nodes().contains(id); }

json& GraphDocument::node_json(const std::string& id) {
  if (!has_node(id)) throw Error("no node \"" + id + "\" in the graph");
  return nodes()[id];
}

const json& GraphDocument::node_json(const std::string& id) const {
  if (!has_node(id)) throw Error("no node \"" + id + "\" in the graph");
  return nodes()[id];
}

std::string GraphDocument::type_name(const std::string& id) const {
  const json& n = node_json(id);
  return n.contains("type") && n["type"].is_string() ? n["type"].get<std::string>() : std::string();
}

const NodeType* GraphDocument::node_type(const std::string& id) const { return declaration(node_json(id), scope()); }

const NodeType* GraphDocument::find_type(const std::string& type) const {
  return group_types_.find(type, scope_groups(), scope().dir);
}

// A Repeat node is declared by its body (loom::repeat_declaration), any
// other node by its type.
const NodeType* GraphDocument::declaration(const json& node, const LevelScope& s) const {
  if (!node.is_object() || !node.contains("type") || !node["type"].is_string()) return nullptr;
  const json& groups = holds_object(*s.root, "groups") ? (*s.root)["groups"] : empty_object();
  const std::string type = node["type"].get<std::string>();
  if (type != "Repeat") return group_types_.find(type, groups, s.dir);
  const json body = node.value("body", json());
  return body.is_string() ? group_types_.repeat(body.get<std::string>(), groups, s.dir) : nullptr;
}

CanvasPoint GraphDocument::position(const std::string& id) const {
  const json& n = node_json(id);
  if (n.contains("ui") && n["ui"].is_object() && n["ui"].contains("pos")) {
    const json& p = n["ui"]["pos"];
    if (p.is_array() && p.size() == 2 && p[0].is_number() && p[1].is_number())
      return {p[0].get<double>(), p[1].get<double>()};
  }
  return {};
}

bool GraphDocument::collapsed(const std::string& id) const {
  const json& n = node_json(id);
  return n.contains("ui") && n["ui"].is_object() && n["ui"].value("collapsed", false);
}

std::optional<Link> GraphDocument::link(const std::string& id, const std::string& input) const {
  const json& n = node_json(id);
  if (!n.contains("inputs") || !n["inputs"].contains(input)) return std::nullopt;
  return input_link(n["inputs"][input]);
}

json GraphDocument::literal(const std::string& id, const std::string& input) const {
  const json& n = node_json(id);
  if (!n.contains("inputs") || !n["inputs"].contains(input)) return nullptr;
  const json& v = n["inputs"][input];
  return input_link(v) ? json() : v;
}

void GraphDocument::begin_edit(std::string label, const std::string& merge_key) {
  history_.record(snapshot(), std::move(label), merge_key);
  group_types_.edited();
  ++revision_;
}

std::string GraphDocument::unique_id(const std::string& type) const {
  const std::string base = snake_case(std::filesystem::path(type).extension() == ".json"
                                          ? std::filesystem::path(type).stem().string()
                                          : type);
  if (!has_node(base)) return base;
  for (int i = 2;; ++i)
    if (!has_node(base + std::to_string(i))) return base + std::to_string(i);
}

std::string GraphDocument::add_node(const std::string& type, CanvasPoint at) {
  if (!find_type(type)) throw Error("unknown node type \"" + type + "\"");
  if (contains_level(type)) throw Error("a node of group " + type + " here would put the group inside itself");
  const std::string id = unique_id(type);
  begin_edit("add " + id);
  nodes()[id] = {{"type", type}, {"ui", {{"pos", {at.x, at.y}}}}};
  return id;
}

void GraphDocument::remove_nodes(const std::vector<std::string>& ids) {
  std::set<std::string> gone;
  for (const auto& id : ids)
    if (has_node(id)) gone.insert(id);
  if (gone.empty()) return;
  begin_edit(gone.size() == 1 ? "delete " + *gone.begin() : "delete " + std::to_string(gone.size()) + " nodes");
  for (const auto& id : gone) nodes().erase(id);
  // Inputs fed by a removed node fall back to their defaults.
  for (auto& [id, node] : nodes().items()) {
    if (!node.contains("inputs")) continue;
    std::vector<std::string> cut;
    for (auto& [input, value] : node["inputs"].items())
      if (auto l = input_link(value); l && gone.count(l->node)) cut.push_back(input);
    for (const auto& input : cut) node["inputs"].erase(input);
  }
}

bool GraphDocument::depends_on(const std::string& node, const std::string& ancestor) const {
  std::vector<std::string> stack{node};
  std::set<std::string> seen;
  while (!stack.empty()) {
    std::string id = stack.back();
    stack.pop_back();
    if (id == ancestor) return true;
    if (!seen.insert(id).second || !has_node(id)) continue;
    const json& n = nodes()[id];
    if (!n.contains("inputs")) continue;
    for (const auto& [input, value] : n["inputs"].items())
      if (auto l = input_link(value)) stack.push_back(l->node);
  }
  return false;
}

std::string GraphDocument::link_refusal(const std::string& from_node, const std::string& output,
                                        const std::string& to_node, const std::string& input) const {
  if (!has_node(from_node) || !has_node(to_node)) return "unknown node";
  const NodeType* from = node_type(from_node);
  const NodeType* to = node_type(to_node);
  if (!from || !to) return "unknown node type";
  const int o = from->spec.output_index(output);
  const InputSpec* in = to->spec.find_input(input);
  if (o < 0) return from_node + " has no output \"" + output + "\"";
  if (!in) return to_node + " has no input \"" + input + "\"";
  const TypeInfo& have = *from->spec.outputs[static_cast<std::size_t>(o)].type;
  if (!link_compatible(have, *in->type))
    return "type mismatch: " + link_text(from_node, output) + " is " + have.name + " but " + to_node +
           "." + input + " expects " + in->type->name;
  if (from_node == to_node || depends_on(from_node, to_node))
    return "would make a cycle: " + from_node + " already depends on " + to_node;
  return {};
}

std::string GraphDocument::connect(const std::string& from_node, const std::string& output,
                                   const std::string& to_node, const std::string& input) {
  std::string refusal = link_refusal(from_node, output, to_node, input);
  if (!refusal.empty()) return refusal;
  begin_edit("link " + link_text(from_node, output) + " -> " + link_text(to_node, input));
  node_json(to_node)["inputs"][input] = {{"from", link_text(from_node, output)}};
  return {};
}

void GraphDocument::disconnect(const std::string& to_node, const std::string& input) {
  if (!link(to_node, input)) return;
  begin_edit("unlink " + link_text(to_node, input));
  node_json(to_node)["inputs"].erase(input);
}

void GraphDocument::set_input(const std::string& id, const std::string& input, json value,
                              const std::string& merge_key) {
  json& n = node_json(id);
  if (n.contains("inputs") && n["inputs"].contains(input) && n["inputs"][input] == value) return;
  begin_edit("set " + link_text(id, input), merge_key);
  node_json(id)["inputs"][input] = std::move(value);
}

void GraphDocument::set_inputs(const std::string& id, const json& values, const std::string& merge_key) {
  const json& n = node_json(id);
  bool same = true;
  for (const auto& [input, value] : values.items()) {
    const bool present = n.contains("inputs") && n["inputs"].contains(input);
    same = same && (value.is_null() ? !present : present && n["inputs"][input] == value);
  }
  if (same) return;
  begin_edit("set " + std::to_string(values.size()) + " inputs of " + id, merge_key);
  json& inputs = node_json(id)["inputs"];
  for (const auto& [input, value] : values.items()) {
    if (value.is_null())
      inputs.erase(input);
    else
      inputs[input] = value;
  }
}

json GraphDocument::evaluated_part() const {
  json doc = doc_;
  doc["loom"] = format_version();
  doc.erase("ui");
  auto strip = [](json& level) {
    if (level.is_object() && level.contains("nodes") && level["nodes"].is_object())
      for (auto& [id, node] : level["nodes"].items())
        if (node.is_object()) node.erase("ui");
  };
  strip(doc);
  if (doc.contains("groups") && doc["groups"].is_object())
    for (auto& [name, group] : doc["groups"].items()) strip(group);
  inline_edited_group_files(doc);
  return doc;
}

namespace {

// A group file's definition as an inline group of another file: its ".json"
// types made absolute (they were relative to its own folder), its layout left out.
json as_inline_group(json def, const std::filesystem::path& folder) {
  def.erase("loom");
  def.erase("groups");
  def.erase("ui");
  if (!holds_object(def, "nodes")) return def;
  for (auto& [id, node] : def["nodes"].items()) {
    if (!node.is_object()) continue;
    node.erase("ui");
    for (const char* key : {"type", "body"}) {
      const json named = node.value(key, json());
      if (!named.is_string()) continue;
      const std::filesystem::path type = named.get<std::string>();
      if (type.extension() == ".json" && type.is_relative()) node[key] = (folder / type).lexically_normal().string();
    }
  }
  return def;
}

}  // namespace

// Group files edited and not saved are evaluated as the editor shows them:
// each becomes an inline group under the very type the graph's nodes name it
// by (the engine looks inline groups up before files), so nothing else of
// the document changes. Its own inline groups come along unless the graph
// has groups of those names; a group file used only by other group files is
// evaluated as saved.
void GraphDocument::inline_edited_group_files(json& doc) const {
  if (edited_group_files().empty()) return;
  std::set<std::string> named;
  auto collect = [&](const json& level) {
    if (!holds_object(level, "nodes")) return;
    for (const auto& [id, node] : level["nodes"].items())
      for (const char* key : {"type", "body"})
        if (node.is_object() && node.contains(key) && node[key].is_string()) named.insert(node[key]);
  };
  collect(doc_);
  for (const auto& [name, group] : groups().items()) collect(group);
  for (const std::string& type : named) {
    const std::filesystem::path* file = group_types_.file_of(type, groups(), dir());
    auto open = file ? files_.find(file->string()) : files_.end();
    if (open == files_.end() || open->second.doc == open->second.saved) continue;
    const json& edited = open->second.doc;
    if (holds_object(edited, "groups"))
      for (const auto& [name, group] : edited["groups"].items())
        if (!doc["groups"].contains(name)) doc["groups"][name] = as_inline_group(group, file->parent_path());
    doc["groups"][type] = as_inline_group(edited, file->parent_path());
  }
}

void GraphDocument::reset_input(const std::string& id, const std::string& input) {
  json& n = node_json(id);
  if (!n.contains("inputs") || !n["inputs"].contains(input)) return;
  begin_edit("reset " + link_text(id, input));
  node_json(id)["inputs"].erase(input);
  if (node_json(id)["inputs"].empty()) node_json(id).erase("inputs");
}

void GraphDocument::move_nodes(const std::vector<std::string>& ids, double dx, double dy,
                               const std::string& merge_key) {
  if (ids.empty() || (dx == 0 && dy == 0)) return;
  begin_edit(ids.size() == 1 ? "move " + ids[0] : "move " + std::to_string(ids.size()) + " nodes", merge_key);
  for (const auto& id : ids) {
    if (!has_node(id)) continue;
    const CanvasPoint p = position(id);
    node_json(id)["ui"]["pos"] = {p.x + dx, p.y + dy};
  }
}

void GraphDocument::set_collapsed(const std::string& id, bool collapsed) {
  if (this->collapsed(id) == collapsed) return;
  begin_edit((collapsed ? "collapse " : "expand ") + id);
  json& ui = node_json(id)["ui"];
  if (collapsed)
    ui["collapsed"] = true;
  else
    ui.erase("collapsed");
}

json GraphDocument::copy(const std::vector<std::string>& ids) const {
  const std::set<std::string> chosen(ids.begin(), ids.end());
  json clip = empty_graph();
  for (const auto& id : chosen) {
    if (!has_node(id)) continue;
    json n = nodes()[id];
    if (n.contains("inputs")) {
      std::vector<std::string> cut;
      for (auto& [input, value] : n["inputs"].items())
        if (auto l = input_link(value); l && !chosen.count(l->node)) cut.push_back(input);
      for (const auto& input : cut) n["inputs"].erase(input);
    }
    clip["nodes"][id] = std::move(n);
  }
  return clip;
}

std::vector<std::string> GraphDocument::paste(const json& clip, double dx, double dy) {
  parse_graph(clip, "<clipboard>");
  if (clip["nodes"].empty()) return {};
  begin_edit("paste " + std::to_string(clip["nodes"].size()) + " nodes");
  std::map<std::string, std::string> renamed;
  for (const auto& [id, n] : clip["nodes"].items()) {
    std::string fresh = has_node(id) ? unique_id(n.value("type", id)) : id;
    renamed[id] = fresh;
    nodes()[fresh] = json::object();  // reserve the id for the next unique_id
  }
  std::vector<std::string> added;
  for (const auto& [id, source] : clip["nodes"].items()) {
    json n = source;
    if (n.contains("inputs"))
      for (auto& [input, value] : n["inputs"].items())
        if (auto l = input_link(value)) {
          auto it = renamed.find(l->node);
          if (it != renamed.end()) value = {{"from", link_text(it->second, l->output)}};
        }
    CanvasPoint p{};
    if (n.contains("ui") && n["ui"].is_object() && n["ui"].contains("pos") && n["ui"]["pos"].is_array() &&
        n["ui"]["pos"].size() == 2)
      p = {n["ui"]["pos"][0].get<double>(), n["ui"]["pos"][1].get<double>()};
    n["ui"]["pos"] = {p.x + dx, p.y + dy};
    nodes()[renamed[id]] = std::move(n);
    added.push_back(renamed[id]);
  }
  return added;
}

std::vector<std::string> GraphDocument::duplicate(const std::vector<std::string>& ids) {
  return paste(copy(ids), 40, 40);
}

std::optional<TimeRange> GraphDocument::time_range() const {
  if (!doc_.contains("time")) return std::nullopt;
  try {
    return parse_graph({{"loom", kGraphFormatVersion}, {"time", doc_["time"]}, {"nodes", json::object()}}, {}).time;
  } catch (const GraphError&) {
    return std::nullopt;  // validation reports it
  }
}

int GraphDocument::frame() const {
  const auto range = time_range();
  if (!range) return 1;
  int f = range->start;
  if (doc_.contains("ui") && doc_["ui"].is_object() && doc_["ui"].contains("frame") &&
      doc_["ui"]["frame"].is_number_integer())
    f = static_cast<int>(std::clamp<long long>(doc_["ui"]["frame"].get<long long>(), range->start, range->end));
  return f;
}

void GraphDocument::set_frame(int frame) {
  if (!doc_.contains("ui") || !doc_["ui"].is_object()) doc_["ui"] = json::object();
  doc_["ui"]["frame"] = frame;
}

// What an undo step keeps: the graph and every group file opened in it.
json GraphDocument::snapshot() const {
  json files = json::object();
  for (const auto& [path, level] : files_) files[path] = level.doc;
  return {{"graph", doc_}, {"files", files}};
}

void GraphDocument::restore(json snapshot) {
  doc_ = std::move(snapshot["graph"]);
  json& files = snapshot["files"];
  // A file opened after the step was recorded was as read then.
  for (auto& [path, level] : files_) level.doc = files.contains(path) ? std::move(files[path]) : level.saved;
}

// The frame is not part of the history: undo and redo keep the current one.
bool GraphDocument::step_history(bool (EditHistory::*step)(json&)) {
  const json ui = doc_.value("ui", json());
  json current = snapshot();
  if (!(history_.*step)(current)) return false;
  restore(std::move(current));
  group_types_.edited();
  trim_path();
  if (ui.is_null())
    doc_.erase("ui");
  else
    doc_["ui"] = ui;
  ++revision_;
  return true;
}

bool GraphDocument::undo() { return step_history(&EditHistory::undo); }
bool GraphDocument::redo() { return step_history(&EditHistory::redo); }

void GraphDocument::place_unplaced_nodes() {
  const LevelScope top{&doc_, dir(), {}};
  place_unplaced_nodes_in(doc_, [&](const json& node) { return declaration(node, top); });
}

}  // namespace loom::editor
