#include "mesh_parts.hpp"

#include <numeric>

namespace loom::arap {

namespace {
int find_root(std::vector<int>& parent, int v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}
}  // namespace

MeshParts mesh_parts(const Eigen::MatrixX3i& F, int n) {
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<bool> used(n, false);
  for (Eigen::Index t = 0; t < F.rows(); ++t)
    for (int i = 0; i < 3; ++i) {
      used[F(t, i)] = true;
      const int a = find_root(parent, F(t, i)), b = find_root(parent, F(t, (i + 1) % 3));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  MeshParts p;
  p.part.assign(n, -1);
  std::vector<int> root_part(n, -1);
  for (int v = 0; v < n; ++v) {
    if (!used[v]) continue;
    const int r = find_root(parent, v);
    if (root_part[r] < 0) {
      root_part[r] = p.count++;
      p.first_vertex.push_back(v);
    }
    p.part[v] = root_part[r];
  }
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
