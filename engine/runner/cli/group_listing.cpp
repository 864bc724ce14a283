#include "cli/group_listing.hpp"

#include <iostream>

#include "loom/graph.hpp"

namespace loom::runner {

std::vector<NodeType> library_node_types(const Registry& registry) {
  std::vector<NodeType> types;
  const auto path = graph_search_path();
  const std::filesystem::path shipped = path.empty() ? std::filesystem::path() : path.back();
  for (const auto& file : library_group_files()) {
    const auto dir = file.parent_path();
    const std::string where = dir == shipped ? "groups: graphs/lib" : "groups: " + dir.string();
    try {
      types.push_back(group_node_type(load_graph_file(file), file.stem().string(), where, registry));
    } catch (const std::exception& e) {
      std::cerr << "warning: group " << file.string() << " skipped: " << e.what() << "\n";
    }
  }
  return types;
}

}  // namespace loom::runner
