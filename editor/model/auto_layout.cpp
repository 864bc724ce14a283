#include "auto_layout.hpp"

#include <map>
#include <string>
#include <vector>

namespace loom::editor {

namespace {
bool is_link(const json& value) {
  return value.is_object() && value.contains("from") && value["from"].is_string() &&
         value["from"].get<std::string>().find('.') != std::string::npos;
}
std::string linked_node(const json& value) {
  const std::string text = value["from"].get<std::string>();
  return text.substr(0, text.find('.'));
}
}  // namespace

// Nodes without a position (hand-written graphs) are laid out in columns by
// their depth along links, so a file opens readable; the placement is only
// written back when the user saves.
void place_unplaced_nodes_in(json& doc, const Registry& registry) {
  std::map<std::string, int> depth;
  std::vector<std::string> ids;
  for (const auto& [id, node] : doc["nodes"].items()) ids.push_back(id);
  bool any_unplaced = false;
  for (const auto& id : ids) {
    const json& n = doc["nodes"][id];
    if (!(n.contains("ui") && n["ui"].is_object() && n["ui"].contains("pos"))) any_unplaced = true;
  }
  if (!any_unplaced) return;
  // Longest path from a source, by relaxation (graphs may still hold a cycle:
  // bounded by the node count).
  for (const auto& id : ids) depth[id] = 0;
  for (std::size_t round = 0; round < ids.size(); ++round) {
    bool changed = false;
    for (const auto& id : ids) {
      const json& n = doc["nodes"][id];
      if (!n.contains("inputs") || !n["inputs"].is_object()) continue;
      for (const auto& [input, value] : n["inputs"].items())
        if (is_link(value) && depth.count(linked_node(value)) && depth[linked_node(value)] + 1 > depth[id]) {
          depth[id] = depth[linked_node(value)] + 1;
          changed = true;
        }
    }
    if (!changed) break;
  }
  // Columns by depth; in a column, nodes stacked by their height on the
  // canvas (a header and footer of ~44 units and 20 per socket row). A column
  // taller than kTall wraps into another, so wide graphs stay near 16:9.
  constexpr double kTall = 1400;
  struct Place {
    std::string id;
    int column, sub;
    double y;
  };
  std::vector<Place> places;
  std::map<int, std::pair<int, double>> cursor;  // column -> (sub-column, next y)
  for (const auto& id : ids) {
    const json& n = doc["nodes"][id];
    if (n.contains("ui") && n["ui"].is_object() && n["ui"].contains("pos")) continue;
    const NodeType* t = registry.find(n.value("type", ""));
    const std::size_t rows = t ? t->spec.inputs.size() + t->spec.outputs.size() : 1;
    const double height = 44.0 + 20.0 * double(rows);
    auto& [sub, y] = cursor.emplace(depth[id], std::make_pair(0, 40.0)).first->second;
    if (y > 40.0 && y + height > kTall) {
      ++sub;
      y = 40.0;
    }
    places.push_back({id, depth[id], sub, y});
    y += height + 40.0;
  }
  std::map<int, int> first_slot;  // column -> its first sub-column's slot
  int slot = 0;
  for (const auto& [column, state] : cursor) {
    first_slot[column] = slot;
    slot += state.first + 1;
  }
  for (const Place& p : places)
    doc["nodes"][p.id]["ui"]["pos"] = {40.0 + 260.0 * (first_slot[p.column] + p.sub), p.y};
}

}  // namespace loom::editor
