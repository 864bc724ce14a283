#include "displacement.hpp"

#include <cstdint>
#include <unordered_map>

#include "loom/numerics/tangent_frames.hpp"
#include "texture.hpp"

namespace loom::pathtrace {

Mesh subdivide_midpoint(const Mesh& m) {
  const Eigen::Index nv = m.V.rows(), nf = m.F.rows();
  std::unordered_map<std::uint64_t, int> midpoint;
  midpoint.reserve(std::size_t(nf) * 3 / 2);
  // New vertex v = (a + b) / 2 for each edge, appended after the old ones.
  std::vector<std::pair<int, int>> edges;
  auto mid = [&](int a, int b) {
    const auto lo = std::uint64_t(std::min(a, b)), hi = std::uint64_t(std::max(a, b));
    const auto [it, inserted] = midpoint.emplace((lo << 32) | hi, int(nv + Eigen::Index(edges.size())));
    if (inserted) edges.emplace_back(a, b);
    return it->second;
  };
  Mesh out;
  out.F.resize(4 * nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const int a = m.F(f, 0), b = m.F(f, 1), c = m.F(f, 2);
    const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    out.F.row(4 * f + 0) << a, ab, ca;
    out.F.row(4 * f + 1) << ab, b, bc;
    out.F.row(4 * f + 2) << ca, bc, c;
    out.F.row(4 * f + 3) << ab, bc, ca;
  }
  const Eigen::Index total = nv + Eigen::Index(edges.size());
  auto grow = [&](const auto& X, auto& Y) {
    if (X.rows() != nv || nv == 0) return;
    Y.resize(total, X.cols());
    Y.topRows(nv) = X;
    for (std::size_t e = 0; e < edges.size(); ++e)
      Y.row(nv + Eigen::Index(e)) = 0.5 * (X.row(edges[e].first) + X.row(edges[e].second));
  };
  grow(m.V, out.V);
  grow(m.UV, out.UV);
  grow(m.N, out.N);
  grow(m.C, out.C);
  return out;
}

Mesh displaced_mesh(const Mesh& mesh, const Image& map, double scale, int level) {
  Mesh m = mesh;
  for (int i = 0; i < level; ++i) m = subdivide_midpoint(m);
  Eigen::MatrixX3d N = m.has_normals() ? Eigen::MatrixX3d(m.N) : numerics::vertex_normals(m.V, m.F);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    const double length = N.row(v).norm();
    if (!(length > 0)) continue;  // no direction to move along
    const Vec2f uv = m.UV.row(v).transpose().cast<float>();
    const double h = texel_bilinear(map, uv).x();
    m.V.row(v) += (h * scale / length) * N.row(v);
  }
  m.N = numerics::vertex_normals(m.V, m.F);
  return m;
}

}  // namespace loom::pathtrace
