// Group files for the editor: the library shown in the node search and the
// file a node's group type names, both by the engine's one search rule
// (loom::find_group_file, loom::library_group_files: a ".json" path relative
// to the naming file, else NAME.json on LOOM_GRAPH_PATH, then Loom's shipped
// graphs/lib; docs/graph-format.md, "Composition").
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "loom/graph.hpp"

namespace loom::editor {

struct LibraryGroup {
  std::string name;  // what a node's "type" says
  std::filesystem::path file;
};
// The library's group files, the first of each name winning, by name.
std::vector<LibraryGroup> list_library_groups();

// The file a group type names, seen from a graph in `graph_dir`: a path
// ending in ".json", or a library name. None when there is no such file.
std::optional<std::filesystem::path> resolve_group_file(const std::string& type,
                                                        const std::filesystem::path& graph_dir);

// Structure only, as parse_graph checks it (a graph with unknown types still
// opens). Throws GraphError.
void check_graph_structure(const json& document, const std::filesystem::path& file);

// A JSON file's text and its value. Throws GraphError naming the file when
// it cannot be read or is not JSON.
json read_json_file(const std::filesystem::path& file, std::string& text);

// A group file's JSON ("inputs", "outputs", "nodes", maybe "groups" and
// "description"). Throws GraphError naming the file when it cannot be read
// or is not a group (no "nodes" object).
json read_group_file(const std::filesystem::path& file);

}  // namespace loom::editor
