// The editor's model: the graph JSON being edited, its layout and its undo
// history. No ImGui here, so it is tested without a window.
//
// The document is kept as the graph file's JSON, so whatever the editor does
// not understand ("description", unknown "ui" keys) survives a round trip, and
// a saved file is exactly what `loom run` reads. Layout lives in each node's
// "ui" field: {"pos": [x, y], "collapsed": true} (canvas units, y down).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "edit_history.hpp"
#include "group_types.hpp"
#include "json_layout.hpp"
#include "loom/graph.hpp"
#include "loom/registry.hpp"

namespace loom::editor {

struct CanvasPoint {
  double x = 0, y = 0;
};

class GraphDocument {
 public:
  explicit GraphDocument(const Registry& registry);

  // A new, empty graph.
  void clear();
  // Throws GraphError (with the file's name) if the file is not a graph.
  void load(const std::filesystem::path& file);
  void load_json(const json& document, const std::filesystem::path& file = {});
  // Atomic write in the layout of the file read (json_layout.hpp: key order,
  // one-line arrays and objects kept); the document becomes clean and `file`
  // its path. Group files an edit changed (edited_group_files()) are
  // written too, each in its own layout.
  void save(const std::filesystem::path& file);
  // The files save() would overwrite that another program changed since
  // they were read or last saved (the graph's file, edited group files):
  // ask before saving over them.
  std::vector<std::filesystem::path> changed_on_disk() const;
  // The text save() writes.
  std::string text() const;

  const json& document() const { return doc_; }
  const std::filesystem::path& file() const { return file_; }
  bool dirty() const { return history_.state() != saved_state_; }
  // Changes on every edit, undo and redo: what the evaluation is keyed on.
  std::uint64_t revision() const { return revision_; }
  const Registry& registry() const { return registry_; }

  // Queries, of the level being edited (the top graph, or the group entered:
  // see "Groups" below). Node ids are sorted.
  std::vector<std::string> node_ids() const;
  bool has_node(const std::string& id) const;
  std::string type_name(const std::string& id) const;
  // Null if unknown. A group node's type is its interface (group_types.hpp).
  const NodeType* node_type(const std::string& id) const;
  // What a "type" names here: a registered type or a group; null if neither.
  const NodeType* find_type(const std::string& type) const;
  CanvasPoint position(const std::string& id) const;
  bool collapsed(const std::string& id) const;
  std::optional<Link> link(const std::string& id, const std::string& input) const;
  // The literal given in the graph, or null when unset or linked.
  json literal(const std::string& id, const std::string& input) const;

  // Edits: each is one undo step. Those taking a merge key collapse with the
  // previous edit of the same key (a drag, a slider held down); call
  // end_merge() when the gesture ends.
  std::string add_node(const std::string& type, CanvasPoint at);
  void remove_nodes(const std::vector<std::string>& ids);
  // Returns why the link is refused (type mismatch, cycle, unknown), or "".
  std::string connect(const std::string& from_node, const std::string& output,
                      const std::string& to_node, const std::string& input);
  // The reason connect() would give, without editing.
  std::string link_refusal(const std::string& from_node, const std::string& output,
                           const std::string& to_node, const std::string& input) const;
  void disconnect(const std::string& to_node, const std::string& input);
  void set_input(const std::string& id, const std::string& input, json value,
                 const std::string& merge_key = {});
  void reset_input(const std::string& id, const std::string& input);  // back to the default
  void move_nodes(const std::vector<std::string>& ids, double dx, double dy,
                  const std::string& merge_key = {});
  void set_collapsed(const std::string& id, bool collapsed);
  void end_merge() { history_.seal(); }
  bool merging() const { return history_.merging(); }
  // Sets several inputs of one node in one undo step; a null value unsets
  // that input (back to its default). For tools whose one gesture changes
  // more than one input (a region drawn as a rectangle drops the polygon).
  void set_inputs(const std::string& id, const json& values, const std::string& merge_key = {});

  // Copy/paste as graph JSON: {"loom": 1, "nodes": {...}} of the given nodes,
  // keeping the links among them and dropping links to nodes outside.
  json copy(const std::vector<std::string>& ids) const;
  // Adds the clipboard's nodes shifted by (dx, dy), renaming ids that are
  // taken and their links; returns the new ids. Throws GraphError if `clip` is
  // not a graph.
  std::vector<std::string> paste(const json& clip, double dx, double dy);
  std::vector<std::string> duplicate(const std::vector<std::string>& ids);

  bool can_undo() const { return history_.can_undo(); }
  bool can_redo() const { return history_.can_redo(); }
  const std::string& undo_label() const { return history_.undo_label(); }
  const std::string& redo_label() const { return history_.redo_label(); }
  bool undo();
  bool redo();

  // The document without layout ("ui" fields): what evaluation depends on.
  // Group files edited and not yet saved are in it as inline groups.
  json evaluated_part() const;

  // The graph's "time" range, or none (no "time", or an invalid one).
  std::optional<TimeRange> time_range() const;
  // The time slider's frame, kept in the graph's "ui" field ({"frame": 12})
  // so the file reopens there: within the time range (its start when unset).
  // Not an edit: no undo step, the document stays clean, undo keeps it.
  int frame() const;
  void set_frame(int frame);

  // A fresh id for a node of this type: "image_warp", "image_warp2", ...
  std::string unique_id(const std::string& type) const;

  // Groups (issue 25; the format is docs/graph-format.md's "Composition").
  // Editing happens one level at a time: the top graph, or an inline group
  // entered through a path of group nodes. Every query and edit above works
  // on that level; entering and leaving are not edits.
  const std::vector<std::string>& path() const { return path_; }  // group node ids, outermost first
  // "look.inner." for the path [look, inner]: how the engine names inner nodes.
  std::string path_prefix() const;
  // Enters group node `id` of this level: an inline group, a group file
  // (read once, then edited in memory and written by save()) or a Repeat
  // node's body. False for a node that is none of those. Throws GraphError
  // when its group file cannot be read.
  bool enter(const std::string& id);
  // Leaves to the first `depth` levels of the path (0: the top graph).
  void leave(std::size_t depth);
  // The inline group being edited, or "" at the top.
  std::string group_name() const;
  // A group instance or a Repeat node: a node that can be entered.
  bool is_group_node(const std::string& id) const;
  bool is_repeat(const std::string& id) const;
  // The body group a Repeat node names ("" for another node).
  std::string repeat_body(const std::string& id) const;
  // Whether the level shown is a Repeat node's body (its nodes are not nodes
  // of the evaluated graph: iterations run apart and keep no values).
  bool in_repeat_body() const;
  // The group file a node's type (or Repeat body) names, or empty (not a group file).
  std::filesystem::path group_file(const std::string& id) const;
  // The group file whose nodes are shown, or empty (the graph or an inline group).
  std::filesystem::path level_file() const;
  // Group files opened by enter() that an edit changed since they were read
  // or saved: save() writes them.
  std::vector<std::filesystem::path> edited_group_files() const;
  // Whether this level has an interface to promote to (a group, or a group file's top).
  bool has_interface() const;
  // This level's interface inputs ({} when none).
  json interface_inputs() const;

  // Replaces the nodes `ids` with a node of a new inline group `name` (a
  // fresh name when empty) whose interface carries the links crossing the
  // selection; returns the new node's id. One undo step.
  std::string group(const std::vector<std::string>& ids, const std::string& name = {});
  // The same, the group written as a group file `file` (the node's type is
  // its path relative to this graph's folder). The file is written at once
  // (atomically); undo restores the graph, not the file.
  std::string group_to_file(const std::vector<std::string>& ids, const std::filesystem::path& file);
  // Puts a group node's inner nodes in its place (ids ID_INNER, made unique)
  // wired as the group wired them; an inline group no node uses any more is
  // dropped. Returns the new ids.
  std::vector<std::string> ungroup(const std::string& id);
  // Adds an interface input feeding node.input of this level (which must have
  // an interface); returns its name.
  std::string promote(const std::string& id, const std::string& input);
  // The interface input bound to node.input, or "".
  std::string promoted_as(const std::string& id, const std::string& input) const;
  // The interface output that node.output is, or "".
  std::string exported_as(const std::string& id, const std::string& output) const;

  // One instance (as `loom run --set look.render.width=640` sets one): inside
  // a group, the node the level was entered from gives values to the
  // group's interface inputs. An inner input is set for that instance only
  // by promoting it (its default the value every instance had, so no other
  // instance changes) and giving the instance `value`: one undo step.
  // Returns the interface input's name.
  std::string set_for_instance(const std::string& id, const std::string& input, json value);
  // The value the entered instance gives interface input `name` (null when
  // unset or linked), and its link.
  json instance_literal(const std::string& name) const;
  std::optional<Link> instance_link(const std::string& name) const;
  void set_instance_input(const std::string& name, json value, const std::string& merge_key = {});
  void reset_instance_input(const std::string& name);
  // The node the level shown was entered from ("" at the top).
  std::string instance_id() const { return path_.empty() ? std::string() : path_.back(); }

  // Group types for the node search: this file's inline groups and the library's.
  std::vector<const NodeType*> group_types() const;
  // Reads the group files again (the library may have changed).
  void rescan_group_files() { group_types_.rescan(); }
  // The top graph's node ids (what the engine evaluates and targets).
  std::vector<std::string> root_node_ids() const;
  // The "type" of every node of the file, inner nodes of inline groups included.
  std::vector<std::string> types_used() const;
  // 2 when the file uses groups (inline, group files, an interface), else 1:
  // what save() writes as "loom".
  int format_version() const;

 private:
  bool step_history(bool (EditHistory::*step)(json&));
  json& node_json(const std::string& id);
  const json& node_json(const std::string& id) const;
  // Where a level's types are looked up: the document holding its inline
  // "groups" (the graph or a group file) and the folder its paths are
  // relative to.
  struct LevelScope {
    const json* root = nullptr;
    std::filesystem::path dir;
    std::filesystem::path file;  // the group file, empty for the graph
  };
  // A group file opened inside the document.
  struct GroupFileLevel {
    json doc;
    JsonLayout layout;      // of the text read, for a faithful save
    std::string read_text;  // what was read or last written: another program's change is seen
    json saved;             // the JSON as read (and laid out) or last written
  };
  // The object holding the level's "nodes": the document, an inline group or a group file.
  json& level();
  const json& level() const;
  const json* level_at(std::size_t depth, LevelScope* scope = nullptr) const;
  LevelScope scope() const;  // of the level shown
  const json& scope_groups() const;
  json& scope_root();
  const NodeType* declaration(const json& node, const LevelScope& scope) const;
  void open_group_file(const std::filesystem::path& file);
  json snapshot() const;
  void inline_edited_group_files(json& doc) const;
  void restore(json snapshot);
  void save_group_files();
  json& instance_inputs();
  const json* instance_node() const;
  json& nodes() { return level()["nodes"]; }
  const json& nodes() const { return level()["nodes"]; }
  std::filesystem::path dir() const;
  const json& groups() const;
  void trim_path();
  bool contains_level(const std::string& type) const;
  void drop_unused_groups();
  std::string add_group_node(const std::string& type, const std::vector<std::string>& ids, const json& inputs);
  void begin_edit(std::string label, const std::string& merge_key = {});
  void place_unplaced_nodes();
  bool depends_on(const std::string& node, const std::string& ancestor) const;

  const Registry& registry_;
  json doc_;
  std::filesystem::path file_;
  EditHistory history_;
  JsonLayout layout_;  // of the file read, or last written
  std::optional<std::string> read_text_;         // what was read from file_ or last written there
  std::map<std::string, GroupFileLevel> files_;  // group files entered, by canonical path
  std::vector<std::string> path_;
  GroupTypes group_types_;
  std::uint64_t saved_state_ = 0;
  std::uint64_t revision_ = 0;
};

}  // namespace loom::editor
