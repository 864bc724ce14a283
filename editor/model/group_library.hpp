// Group files found by name: the folders of LOOM_GRAPH_PATH (':'-separated),
// then Loom's shipped graphs/lib/. A node whose "type" is NAME uses the first
// NAME.json found; a type ending in ".json" is a path relative to the file
// that names it (docs/graph-format.md, "Composition").
//
// The editor reads the files itself until the engine offers a loader for
// group files; read_group_file() is the one place that does, so it can be
// swapped for the engine's.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "loom/graph.hpp"

namespace loom::editor {

// LOOM_GRAPH_PATH's folders, then the shipped library (the source tree's
// graphs/lib for a build, <prefix>/share/loom/graphs/lib for an install).
std::vector<std::filesystem::path> group_library_folders();

struct LibraryGroup {
  std::string name;  // what a node's "type" says
  std::filesystem::path file;
};
// The NAME.json files of the folders, the first of each name winning, by name.
std::vector<LibraryGroup> list_library_groups(const std::vector<std::filesystem::path>& folders);

// The file a group type names, seen from a graph in `graph_dir`: a path
// ending in ".json", or a library name. None when there is no such file.
std::optional<std::filesystem::path> resolve_group_file(const std::string& type,
                                                        const std::filesystem::path& graph_dir,
                                                        const std::vector<std::filesystem::path>& folders);

// Structure only, as parse_graph checks it (a graph with unknown types still
// opens). A version-2 file whose version the engine refuses (before
// the engine's composition is merged) is checked level by level: the top
// graph's nodes and each inline group's, as version-1 graphs, with the
// pointers of the issues into the file (/groups/NAME/nodes/...). Throws
// GraphError.
void check_graph_structure(const json& document, const std::filesystem::path& file);

// A JSON file's text and its value. Throws GraphError naming the file when
// it cannot be read or is not JSON.
json read_json_file(const std::filesystem::path& file, std::string& text);

// A group file's JSON ("inputs", "outputs", "nodes", maybe "groups" and
// "description"). Throws GraphError naming the file when it cannot be read
// or is not a group (no "nodes" object).
json read_group_file(const std::filesystem::path& file);

}  // namespace loom::editor
