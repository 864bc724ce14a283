#include "mesh_parts.hpp"

#include "loom/numerics/mesh_topology.hpp"

namespace loom::arap {

MeshParts mesh_parts(const Eigen::MatrixX3i& F, int n) {
  MeshParts p;
  p.part = numerics::connected_components(F, n, &p.count);
  p.first_vertex.assign(static_cast<std::size_t>(p.count), -1);
  for (int v = n - 1; v >= 0; --v)
    if (p.part[static_cast<std::size_t>(v)] >= 0) p.first_vertex[static_cast<std::size_t>(p.part[static_cast<std::size_t>(v)])] = v;
  return p;
}

std::vector<std::array<int, 2>> far_apart_pairs(const Eigen::MatrixX3d& V, const MeshParts& parts) {
  std::vector<std::array<int, 2>> pairs(parts.count);
  auto farthest_from = [&](const std::vector<int>& from) {
    std::vector<int> best(parts.count, -1);
    std::vector<double> dist(parts.count, -1);
    for (int v = 0; v < static_cast<int>(parts.part.size()); ++v) {
      const int k = parts.part[v];
      if (k < 0) continue;
      const double d = (V.row(v) - V.row(from[k])).squaredNorm();
      if (d > dist[k]) dist[k] = d, best[k] = v;
    }
    return best;
  };
  const std::vector<int> a = farthest_from(parts.first_vertex);
  const std::vector<int> b = farthest_from(a);
  for (int k = 0; k < parts.count; ++k) pairs[k] = {a[k], b[k]};
  return pairs;
}

}  // namespace loom::arap
