#include "indexed_mesh.hpp"

#include <array>
#include <cmath>
#include <cstring>
#include <map>

#include "loom/error.hpp"

namespace loom::io {

namespace {

// Each polygon as a fan from its first corner, in output vertex indices; a
// polygon that repeats a vertex has no area or orientation and is left out.
std::vector<Eigen::Vector3i> fan_triangles(const IndexedMesh& m, const std::vector<int>& corner_out, MeshNotes& n) {
  std::vector<Eigen::Vector3i> F;
  const std::size_t np = m.polygon_start.size() - 1;
  F.reserve(m.corner_v.size());
  for (std::size_t p = 0; p < np; ++p) {
    const int b = m.polygon_start[p], e = m.polygon_start[p + 1];
    bool repeated = false;
    for (int i = b; i < e && !repeated; ++i)
      for (int j = i + 1; j < e && !repeated; ++j)
        repeated = m.corner_v[static_cast<std::size_t>(i)] == m.corner_v[static_cast<std::size_t>(j)];
    if (repeated) {
      ++n.degenerate_faces;
      continue;
    }
    for (int i = b + 1; i + 1 < e; ++i)  // fan from the first corner
      F.emplace_back(corner_out[static_cast<std::size_t>(b)], corner_out[static_cast<std::size_t>(i)],
                     corner_out[static_cast<std::size_t>(i + 1)]);
  }
  return F;
}

template <class Matrix, class Row>
void fill_rows(Matrix& out, const std::vector<Row>& rows) {
  out.resize(static_cast<Eigen::Index>(rows.size()), Row::RowsAtCompileTime);
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = rows[i].transpose();
}

// The Mesh of per-vertex rows; UV, N and C only when every vertex has one.
Mesh assemble(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3i>& F,
              const std::vector<Eigen::Vector2d>& UV, const std::vector<Eigen::Vector3d>& N,
              const std::vector<Eigen::Vector3d>& C) {
  Mesh mesh;
  fill_rows(mesh.V, V);
  fill_rows(mesh.F, F);
  if (!UV.empty()) fill_rows(mesh.UV, UV);
  if (!N.empty()) fill_rows(mesh.N, N);
  if (C.size() == V.size()) fill_rows(mesh.C, C);
  return mesh;
}

}  // namespace

Mesh to_mesh(const IndexedMesh& m, const std::string& file, MeshNotes* notes) {
  const int nv = static_cast<int>(m.V.size());
  const int ncorners = static_cast<int>(m.corner_v.size());
  auto all_set = [&](const std::vector<int>& idx) {
    if (static_cast<int>(idx.size()) != ncorners || ncorners == 0) return false;
    for (int i : idx)
      if (i < 0) return false;
    return true;
  };
  const bool uv = all_set(m.corner_uv), normals = all_set(m.corner_n);
  MeshNotes local;
  MeshNotes& n = notes ? *notes : local;
  n.dropped_primitives = m.dropped;
  if (!uv && !m.corner_uv.empty())
    n.messages.push_back("texture coordinates ignored: not every face corner has one");
  if (!normals && !m.corner_n.empty())
    n.messages.push_back("normals ignored: not every face corner has one");

  // Vertex v keeps its index for the first attributes seen at it; other
  // attribute values at v become new vertices appended in order of appearance.
  std::vector<Eigen::Vector3d> V(m.V.begin(), m.V.end());
  std::vector<Eigen::Vector2d> UV(uv ? static_cast<std::size_t>(nv) : 0, Eigen::Vector2d::Zero());
  std::vector<Eigen::Vector3d> N(normals ? static_cast<std::size_t>(nv) : 0, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> C(m.C.begin(), m.C.end());
  std::vector<char> claimed(static_cast<std::size_t>(nv), 0);
  std::multimap<int, int> splits;  // file vertex -> added vertices
  auto same = [&](int out, int corner) {
    if (uv && UV[static_cast<std::size_t>(out)] != m.UV[static_cast<std::size_t>(m.corner_uv[static_cast<std::size_t>(corner)])]) return false;
    if (normals && N[static_cast<std::size_t>(out)] != m.N[static_cast<std::size_t>(m.corner_n[static_cast<std::size_t>(corner)])]) return false;
    return true;
  };
  auto assign = [&](int out, int corner) {
    if (uv) UV[static_cast<std::size_t>(out)] = m.UV[static_cast<std::size_t>(m.corner_uv[static_cast<std::size_t>(corner)])];
    if (normals) N[static_cast<std::size_t>(out)] = m.N[static_cast<std::size_t>(m.corner_n[static_cast<std::size_t>(corner)])];
  };
  std::vector<int> corner_out(static_cast<std::size_t>(ncorners));
  for (int c = 0; c < ncorners; ++c) {
    const int v = m.corner_v[static_cast<std::size_t>(c)];
    if (v < 0 || v >= nv) throw Error(file + ": face index " + std::to_string(v) + " out of range");
    if (!claimed[static_cast<std::size_t>(v)]) {
      claimed[static_cast<std::size_t>(v)] = 1;
      assign(v, c);
      corner_out[static_cast<std::size_t>(c)] = v;
      continue;
    }
    int out = same(v, c) ? v : -1;
    for (auto [it, end] = splits.equal_range(v); out < 0 && it != end; ++it)
      if (same(it->second, c)) out = it->second;
    if (out < 0) {
      out = static_cast<int>(V.size());
      V.push_back(m.V[static_cast<std::size_t>(v)]);
      if (uv) UV.emplace_back();
      if (normals) N.emplace_back();
      if (!C.empty()) C.push_back(m.C[static_cast<std::size_t>(v)]);
      assign(out, c);
      splits.emplace(v, out);
      ++n.split_vertices;
    }
    corner_out[static_cast<std::size_t>(c)] = out;
  }

  const std::vector<Eigen::Vector3i> F = fan_triangles(m, corner_out, n);
  if (F.empty()) throw Error(file + " has no faces");
  if (n.degenerate_faces > 0)
    n.messages.push_back("left out " + std::to_string(n.degenerate_faces) +
                         " faces that repeat a vertex (no area, no orientation)");

  return assemble(V, F, UV, N, C);
}

int weld_vertices(Mesh& mesh, double tolerance) {
  const int nv = mesh.vertices();
  // Cells of size tolerance (or exact positions): a vertex joins the first
  // earlier representative within tolerance in its own or a neighbouring cell.
  const double cell = tolerance > 0 ? tolerance : 1.0;
  auto key = [&](const Eigen::Vector3d& p) -> std::array<long long, 3> {
    if (tolerance <= 0) {
      std::array<long long, 3> k{};
      for (int d = 0; d < 3; ++d) {
        double x = p[d] == 0 ? 0.0 : p[d];  // -0 and +0 are one position
        std::memcpy(&k[static_cast<std::size_t>(d)], &x, sizeof x);
      }
      return k;
    }
    return {static_cast<long long>(std::floor(p.x() / cell)), static_cast<long long>(std::floor(p.y() / cell)),
            static_cast<long long>(std::floor(p.z() / cell))};
  };
  std::map<std::array<long long, 3>, std::vector<int>> grid;
  std::vector<int> target(static_cast<std::size_t>(nv));
  std::vector<int> kept;
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d p = mesh.V.row(v).transpose();
    const auto k = key(p);
    int found = -1;
    if (tolerance <= 0) {
      auto it = grid.find(k);
      if (it != grid.end()) found = it->second.front();
    } else {
      for (long long dx = -1; dx <= 1 && found < 0; ++dx)
        for (long long dy = -1; dy <= 1 && found < 0; ++dy)
          for (long long dz = -1; dz <= 1 && found < 0; ++dz) {
            auto it = grid.find({k[0] + dx, k[1] + dy, k[2] + dz});
            if (it == grid.end()) continue;
            for (int r : it->second)
              if ((mesh.V.row(kept[static_cast<std::size_t>(r)]).transpose() - p).norm() <= tolerance) {
                found = r;
                break;
              }
          }
    }
    if (found >= 0) {
      target[static_cast<std::size_t>(v)] = found;
    } else {
      target[static_cast<std::size_t>(v)] = static_cast<int>(kept.size());
      grid[k].push_back(static_cast<int>(kept.size()));
      kept.push_back(v);
    }
  }
  const int merged = nv - static_cast<int>(kept.size());
  if (merged == 0) return 0;
  Mesh out;
  const auto nk = static_cast<Eigen::Index>(kept.size());
  auto gather = [&](const auto& from, auto& to) {
    if (from.rows() != nv) return;
    to.resize(nk, from.cols());
    for (Eigen::Index i = 0; i < nk; ++i) to.row(i) = from.row(kept[static_cast<std::size_t>(i)]);
  };
  gather(mesh.V, out.V);
  gather(mesh.UV, out.UV);
  gather(mesh.N, out.N);
  gather(mesh.C, out.C);
  std::vector<Eigen::Vector3i> F;
  for (int f = 0; f < mesh.faces(); ++f) {
    Eigen::Vector3i t;
    for (int k = 0; k < 3; ++k) t[k] = target[static_cast<std::size_t>(mesh.F(f, k))];
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) F.push_back(t);
  }
  out.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (std::size_t f = 0; f < F.size(); ++f) out.F.row(static_cast<Eigen::Index>(f)) = F[f].transpose();
  mesh = std::move(out);
  return merged;
}

}  // namespace loom::io
