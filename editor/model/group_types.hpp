// Group types as node types, so the canvas, the properties panel, the link
// rule and the search treat a group node like any other node: its inputs as
// the interface declares them (type, default, min, max, choices, optional,
// description), its outputs typed by the inner outputs they come from.
//
// A node's "type" names, in this order: a registered node type, an inline
// group of the document's top-level "groups", or a group file (a path ending
// in ".json", or a name looked up in the library folders).
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "group_library.hpp"
#include "loom/registry.hpp"

namespace loom::editor {

// Where a group's inner node types are looked up.
using InnerTypeLookup = std::function<const NodeType*(const std::string& type)>;

// The node type of a group `definition` (an inline group, or a group file's
// JSON): run is null, spec.plugin says where it comes from.
NodeType interface_node_type(const std::string& name, const std::string& origin, const json& definition,
                         const InnerTypeLookup& inner);

class GroupTypes {
 public:
  explicit GroupTypes(const Registry& registry);

  // The type `type` names inside a document whose top-level "groups" are
  // `groups` and whose file lies in `dir`; null when it names nothing known.
  const NodeType* find(const std::string& type, const json& groups, const std::filesystem::path& dir) const;
  bool is_group(const std::string& type, const json& groups, const std::filesystem::path& dir) const;
  // A Repeat node's declaration for its body group `body` (the engine's
  // rule, loom::repeat_declaration); null when the body is no group.
  const NodeType* repeat(const std::string& body, const json& groups, const std::filesystem::path& dir) const;
  // The group file (canonical) a type names from `dir`, or null: an inline
  // group or a registered type names none.
  const std::filesystem::path* file_of(const std::string& type, const json& groups,
                                       const std::filesystem::path& dir) const;
  // Group files opened for editing: their types come from this JSON, not
  // from the disk. `open` takes a canonical path; null when not open.
  using OpenFiles = std::function<const json*(const std::filesystem::path& file)>;
  void set_open_files(OpenFiles open) { open_ = std::move(open); }
  // The library's groups (LOOM_GRAPH_PATH, graphs/lib), for the search.
  std::vector<const NodeType*> library() const;

  // Inline definitions may have changed (an edit, undo): their types are
  // rebuilt on demand; those of the previous generation stay valid until the
  // next call, so a pointer taken before an edit survives it.
  void edited();
  // Group files may have changed: read them again.
  void rescan();

 private:
  const NodeType* inline_type(const std::string& name, const json& groups, const std::filesystem::path& dir) const;
  const NodeType* file_type(const std::filesystem::path& file) const;

  // Where a type names a file, by "DIR\nTYPE" (empty: nowhere): the canvas
  // asks for a node's type many times a frame, the disk is asked once.
  const std::filesystem::path* resolved(const std::string& type, const std::filesystem::path& dir) const;

  const Registry& registry_;
  mutable std::map<std::string, std::filesystem::path> resolved_;
  mutable std::optional<std::vector<LibraryGroup>> library_;
  const NodeType* open_file_type(const std::filesystem::path& file, const json& doc) const;

  OpenFiles open_;
  // Built from the document's JSON (inline groups, open files, Repeat
  // bodies): rebuilt after every edit. From the disk: kept until rescan().
  mutable std::map<std::string, std::unique_ptr<NodeType>> inline_, opened_, repeats_, files_;
  mutable std::vector<std::unique_ptr<NodeType>> retired_;
  mutable std::set<std::string> resolving_;  // guards a group that uses itself
};

}  // namespace loom::editor
