#include "loom/numerics/mesh_topology.hpp"

#include <algorithm>
#include <numeric>
#include <cstdint>
#include <string>

#include "loom/error.hpp"

namespace loom::numerics {

namespace {

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) |
         static_cast<std::uint32_t>(std::max(a, b));
}

}  // namespace

// Boundary edges are the undirected edges used by exactly one face; sorting
// the 3·#F edge keys finds them (and the non-manifold ones) without hashing.
// Each boundary half-edge a→b keeps the face's orientation, so following
// "the boundary half-edge that starts where this one ends" walks a loop.
std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixX3i& F, const std::function<void()>& check) {
  auto checkpoint = [&check] {
    if (check) check();
  };
  const int m = static_cast<int>(F.rows());
  std::vector<std::pair<std::uint64_t, int>> edges;  // key, half-edge index 3f+k
  edges.reserve(3 * static_cast<size_t>(m));
  for (int f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) edges.emplace_back(edge_key(F(f, k), F(f, (k + 1) % 3)), 3 * f + k);
  checkpoint();
  std::sort(edges.begin(), edges.end());
  checkpoint();

  std::vector<std::pair<int, int>> boundary;  // directed a→b
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    const int h = edges[i].second, f = h / 3, k = h % 3;
    const int a = F(f, k), b = F(f, (k + 1) % 3);
    if (j - i > 2)
      throw Error("non-manifold edge (" + std::to_string(std::min(a, b)) + ", " +
                  std::to_string(std::max(a, b)) + ") is used by " + std::to_string(j - i) +
                  " faces; a surface edge may border at most two");
    if (j - i == 1) boundary.emplace_back(a, b);
    i = j;
  }
  if (boundary.empty()) return {};
  checkpoint();

  // Outgoing boundary half-edges per vertex; a vertex where two loops touch
  // (a "bowtie") has several, and each is used once.
  std::sort(boundary.begin(), boundary.end());
  std::vector<bool> used(boundary.size(), false);
  auto first_out = [&](int v) {
    return std::lower_bound(boundary.begin(), boundary.end(), std::make_pair(v, -1)) -
           boundary.begin();
  };
  std::vector<std::vector<int>> loops;
  for (size_t s = 0; s < boundary.size(); ++s) {
    if (used[s]) continue;
    std::vector<int> loop;
    size_t e = s;
    while (true) {
      used[e] = true;
      loop.push_back(boundary[e].first);
      const int next = boundary[e].second;
      if (next == boundary[s].first) break;
      size_t c = first_out(next);
      while (c < boundary.size() && boundary[c].first == next && used[c]) ++c;
      if (c >= boundary.size() || boundary[c].first != next) break;  // open chain (inconsistent orientation)
      e = c;
    }
    loops.push_back(std::move(loop));
  }
  std::stable_sort(loops.begin(), loops.end(),
                   [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return loops;
}

std::vector<std::vector<int>> vertex_adjacency(const Eigen::MatrixX3i& F, int n) {
  std::vector<std::vector<int>> adj(n);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      adj[a].push_back(b);
      adj[b].push_back(a);
    }
  for (auto& list : adj) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return adj;
}

std::vector<bool> referenced_vertices(const Eigen::MatrixX3i& F, int n) {
  std::vector<bool> used(n, false);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[F(f, k)] = true;
  return used;
}

std::vector<int> connected_components(const Eigen::MatrixX3i& F, int n, int* count) {
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&parent](int v) {
    while (parent[static_cast<std::size_t>(v)] != v)
      v = parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    return v;
  };
  std::vector<char> used(static_cast<std::size_t>(n), 0);
  for (Eigen::Index t = 0; t < F.rows(); ++t)
    for (int i = 0; i < 3; ++i) {
      used[static_cast<std::size_t>(F(t, i))] = 1;
      const int a = root(F(t, i)), b = root(F(t, (i + 1) % 3));
      if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
  std::vector<int> component(static_cast<std::size_t>(n), -1), numbered(static_cast<std::size_t>(n), -1);
  int k = 0;
  for (int v = 0; v < n; ++v) {
    if (!used[static_cast<std::size_t>(v)]) continue;
    int& c = numbered[static_cast<std::size_t>(root(v))];
    if (c < 0) c = k++;
    component[static_cast<std::size_t>(v)] = c;
  }
  if (count) *count = k;
  return component;
}

}  // namespace loom::numerics
