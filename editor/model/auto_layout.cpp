#include "auto_layout.hpp"

#include "input_link.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace loom::editor {

namespace {

bool placed(const json& node) {
  return node.is_object() && node.contains("ui") && node["ui"].is_object() && node["ui"].contains("pos") &&
         node["ui"]["pos"].is_array() && node["ui"]["pos"].size() == 2 && node["ui"]["pos"][0].is_number() &&
         node["ui"]["pos"][1].is_number();
}

// Longest path from a source, by relaxation (graphs may still hold a cycle:
// bounded by the node count).
std::map<std::string, int> depths(const json& nodes) {
  std::map<std::string, int> depth;
  for (const auto& [id, node] : nodes.items()) depth[id] = 0;
  for (std::size_t round = 0; round < depth.size(); ++round) {
    bool changed = false;
    for (const auto& [id, n] : nodes.items()) {
      if (!n.is_object() || !n.contains("inputs") || !n["inputs"].is_object()) continue;
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
  return depth;
}

}  // namespace

// Nodes without a position (hand-written graphs) are laid out in columns by
// their depth along links, so a file opens readable; the placement is only
// written back when the user saves.
void place_unplaced_nodes_in(json& doc, const TypeLookup& type_of) {
  json& nodes = doc["nodes"];
  std::vector<CanvasRect> taken;  // placed nodes, then each node as it is placed
  bool any_unplaced = false;
  for (const auto& [id, node] : nodes.items()) {
    if (!placed(node)) {
      any_unplaced = true;
      continue;
    }
    taken.push_back({node["ui"]["pos"][0].get<double>(), node["ui"]["pos"][1].get<double>(), kNodeWidth,
                     node_height(type_of(node))});
  }
  if (!any_unplaced) return;
  const std::map<std::string, int> depth = depths(nodes);
  // Columns by depth; in a column, nodes stacked by their height. A column
  // taller than kTall wraps into another, so wide graphs stay near 16:9.
  constexpr double kTall = 1400, kGap = 40, kColumn = 280;
  struct Place {
    std::string id;
    int column, sub;
    double y, height;
  };
  std::vector<Place> places;
  std::map<int, std::pair<int, double>> cursor;  // column -> (sub-column, next y)
  for (const auto& [id, node] : nodes.items()) {
    if (placed(node)) continue;
    const double height = node_height(type_of(node));
    auto& [sub, y] = cursor.emplace(depth.at(id), std::make_pair(0, kGap)).first->second;
    if (y > kGap && y + height > kTall) {
      ++sub;
      y = kGap;
    }
    places.push_back({id, depth.at(id), sub, y, height});
    y += height + kGap;
  }
  std::map<int, int> first_slot;  // column -> its first sub-column's slot
  int slot = 0;
  for (const auto& [column, state] : cursor) {
    first_slot[column] = slot;
    slot += state.first + 1;
  }
  for (const Place& p : places) {
    const CanvasPoint wanted{kGap + kColumn * (first_slot[p.column] + p.sub), p.y};
    // Columns never overlap each other; a node placed by hand may be in the way.
    const CanvasPoint at = free_spot(taken, wanted, kNodeWidth, p.height);
    taken.push_back({at.x, at.y, kNodeWidth, p.height});
    nodes[p.id]["ui"]["pos"] = {at.x, at.y};
  }
}

double node_height(const NodeType* type) {
  const std::size_t rows = type ? type->spec.inputs.size() + type->spec.outputs.size() : 1;
  return kNodeHeader + kNodeFooter + kNodeRow * double(rows);
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
