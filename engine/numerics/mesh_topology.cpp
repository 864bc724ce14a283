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

// The half-edges (key, 3f+k) in the order of sorting the pairs, by a counting
// sort on the smaller vertex and a sort of each (short) bucket: linear time,
// and `check` runs every 2^20 half-edges (one std::sort of 3M pairs took
// 0.3 s that Ctrl-C had to wait for).
std::vector<std::pair<std::uint64_t, int>> sorted_half_edges(const Eigen::MatrixX3i& F,
                                                             const std::function<void()>& check) {
  const int m = static_cast<int>(F.rows());
  const std::size_t count = 3 * static_cast<std::size_t>(m);
  auto every_chunk = [&](std::size_t h) {
    if (check && h % (std::size_t(1) << 20) == 0) check();
  };
  if (m > 0 && F.minCoeff() < 0) throw Error("a face has a negative vertex index");
  const int n = m > 0 ? F.maxCoeff() + 1 : 0;
  std::vector<std::size_t> start(static_cast<std::size_t>(n) + 1, 0);
  for (std::size_t h = 0; h < count; ++h) {
    every_chunk(h);
    const int f = static_cast<int>(h / 3), k = static_cast<int>(h % 3);
    ++start[static_cast<std::size_t>(std::min(F(f, k), F(f, (k + 1) % 3))) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::pair<std::uint64_t, int>> edges(count);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t h = 0; h < count; ++h) {
    every_chunk(h);
    const int f = static_cast<int>(h / 3), k = static_cast<int>(h % 3);
    const int a = F(f, k), b = F(f, (k + 1) % 3);
    edges[fill[static_cast<std::size_t>(std::min(a, b))]++] = {edge_key(a, b), static_cast<int>(h)};
  }
  for (int v = 0; v < n; ++v) {
    if (check && start[static_cast<std::size_t>(v)] >> 20 != start[static_cast<std::size_t>(v) + 1] >> 20) check();
    std::sort(edges.begin() + static_cast<std::ptrdiff_t>(start[static_cast<std::size_t>(v)]),
              edges.begin() + static_cast<std::ptrdiff_t>(start[static_cast<std::size_t>(v) + 1]));
  }
  return edges;
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
  const std::vector<std::pair<std::uint64_t, int>> edges = sorted_half_edges(F, check);  // key, half-edge 3f+k

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
