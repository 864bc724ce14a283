#include "closed_surface.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <tbb/parallel_sort.h>

#include "gl_api.hpp"
#include "loom/numerics/mesh_topology.hpp"

namespace loom::shading {

namespace {

// Each vertex's representative: the first of those whose positions round to
// the same cell of side 1e-6 of the extent. Two points straddling a cell
// border stay apart (the mesh then counts as open: no culling, never a
// wrong image).
std::vector<int> welded(const Eigen::MatrixX3d& V) {
  const Eigen::RowVector3d lo = V.colwise().minCoeff();
  const double cell = std::max((V.colwise().maxCoeff() - lo).norm() * 1e-6, 1e-300);
  using Key = std::array<long long, 3>;
  std::vector<std::pair<Key, int>> keys(static_cast<std::size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const Eigen::RowVector3d q = (V.row(i) - lo) / cell;
    keys[i] = {{std::llround(q.x()), std::llround(q.y()), std::llround(q.z())}, static_cast<int>(i)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<int> rep(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k)
    rep[keys[k].second] = k > 0 && keys[k].first == keys[k - 1].first ? rep[keys[k - 1].second] : keys[k].second;
  return rep;
}

}  // namespace

int closed_orientation(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  if (V.rows() == 0 || F.rows() == 0 || !V.allFinite()) return 0;
  const std::vector<int> rep = welded(V);
  Eigen::MatrixX3i W(F.rows(), 3);
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * static_cast<std::size_t>(F.rows()));
  Eigen::Index m = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int a = rep[F(f, 0)], b = rep[F(f, 1)], c = rep[F(f, 2)];
    if (a == b || b == c || c == a) continue;
    W.row(m++) << a, b, c;
    // The undirected edge, then which way this face runs it (indices < 2^31).
    for (auto [u, v] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
      edges.push_back(std::uint64_t(std::min(u, v)) << 32 | std::uint64_t(std::max(u, v)) << 1 | (u > v));
  }
  if (m == 0) return 0;
  // Closed and consistently oriented: each edge exactly twice, once each way.
  tbb::parallel_sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size(); i += 2)
    if (i + 1 == edges.size() || edges[i] >> 1 != edges[i + 1] >> 1 || (edges[i] & 1) || !(edges[i + 1] & 1)) return 0;
  // Signed volume of each part (divergence theorem: sum of det(a, b, c) / 6),
  // about the bounds' center for precision.
  int parts = 0;
  const std::vector<int> part = numerics::connected_components(W.topRows(m), static_cast<int>(V.rows()), &parts);
  const Eigen::RowVector3d o = (V.colwise().minCoeff() + V.colwise().maxCoeff()) / 2;
  std::vector<double> volume(static_cast<std::size_t>(parts), 0.0);
  for (Eigen::Index f = 0; f < m; ++f) {
    const Eigen::Vector3d a = V.row(W(f, 0)) - o, b = V.row(W(f, 1)) - o, c = V.row(W(f, 2)) - o;
    volume[part[W(f, 0)]] += a.dot(b.cross(c)) / 6;
  }
  const bool outward = std::all_of(volume.begin(), volume.end(), [](double v) { return v > 0; });
  const bool inward = std::all_of(volume.begin(), volume.end(), [](double v) { return v < 0; });
  return outward ? 1 : inward ? -1 : 0;
}

unsigned hidden_side(int orientation, const Eigen::AlignedBox3d& bounds, const Eigen::Matrix4d& model,
                     const Eigen::Matrix4d& view, double near_plane) {
  if (orientation == 0 || bounds.isEmpty()) return 0;
  const Eigen::Matrix4d to_view = view * model;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner = bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k));
    if ((to_view * corner.homogeneous()).z() >= -near_plane) return 0;
  }
  // A mirroring model matrix turns an outward winding inward on screen.
  const bool mirrored = model.topLeftCorner<3, 3>().determinant() < 0;
  return (orientation > 0) != mirrored ? GL_BACK : GL_FRONT;
}

}  // namespace loom::shading
