// The add-node menu's search: node types ranked by how they match what was
// typed, as a user expects from Blender's or Houdini's search — the name
// typed exactly, then names starting with it, then a word of a name
// (SmoothMesh's "Mesh") starting with it, then names containing it, then the
// plugin's name, then the description. Searching "smooth" offers SmoothMesh
// before HeightMap (whose description mentions smooth bumps).
#pragma once

#include <string>
#include <vector>

#include "loom/registry.hpp"

namespace loom::editor {

enum class SearchMatch { exact, prefix, word, inside, plugin, description, none };

// How a type matches the query (case-insensitive; spaces in the query are
// ignored for names, so "save image" finds SaveImage).
SearchMatch match_node_type(const NodeSpec& spec, const std::string& query);
// The matching types, best first (then by name); an empty query lists all.
std::vector<const NodeType*> search_node_types(const Registry& registry, const std::string& query);
// The same over any types (the registry's and the groups', graph_document.hpp).
std::vector<const NodeType*> search_node_types(std::vector<const NodeType*> candidates, const std::string& query);

}  // namespace loom::editor
