#include "auto_layout.hpp"

#include "input_link.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace loom::editor {

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
      for (const auto& [input, value] : n["inputs"].items()) {
        const auto link = input_link(value);
        if (link && depth.count(link->node) && depth[link->node] + 1 > depth[id]) {
          depth[id] = depth[link->node] + 1;
          changed = true;
        }
      }
    }
    if (!changed) break;
  }
  // Columns by depth; in a column, nodes stacked by their height on the
  // canvas (a header and footer of ~48 units and 22 per socket row). A column
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
    const double height = node_height(registry.find(n.value("type", "")));
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
    doc["nodes"][p.id]["ui"]["pos"] = {40.0 + 280.0 * (first_slot[p.column] + p.sub), p.y};
}

double node_height(const NodeType* type) {
  const std::size_t rows = type ? type->spec.inputs.size() + type->spec.outputs.size() : 1;
  return 48.0 + 22.0 * double(rows);
}

CanvasPoint free_spot(const std::vector<CanvasRect>& taken, CanvasPoint wanted, double width, double height) {
  constexpr double kMargin = 16, kStep = 20;
  constexpr int kReach = 40;  // steps each way: 800 canvas units
  auto free = [&](double x, double y) {
    for (const CanvasRect& r : taken)
      if (x < r.x + r.width + kMargin && r.x < x + width + kMargin && y < r.y + r.height + kMargin &&
          r.y < y + height + kMargin)
        return false;
    return true;
  };
  std::vector<std::pair<int, int>> steps;
  for (int j = -kReach; j <= kReach; ++j)
    for (int i = -kReach; i <= kReach; ++i) steps.emplace_back(i, j);
  // Nearest first; at equal distance, right and below before left and above.
  std::sort(steps.begin(), steps.end(), [](auto a, auto b) {
    const int da = a.first * a.first + a.second * a.second, db = b.first * b.first + b.second * b.second;
    return da != db ? da < db : a.second != b.second ? a.second > b.second : a.first > b.first;
  });
  for (const auto& [i, j] : steps)
    if (free(wanted.x + i * kStep, wanted.y + j * kStep)) return {wanted.x + i * kStep, wanted.y + j * kStep};
  return wanted;
}

}  // namespace loom::editor
