#include "tutte_map.hpp"

#include <cmath>
#include <vector>

#include "loom/error.hpp"
#include "loom/numerics/laplacian.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "loom/numerics/sparse_solver.hpp"
#include "mesh_parts.hpp"

namespace loom::arap {

Eigen::MatrixX2d tutte_map(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& faces) {
  const int n = static_cast<int>(V.rows());
  // Faces with a repeated vertex have no area and no place in the topology.
  std::vector<int> proper;
  for (Eigen::Index t = 0; t < faces.rows(); ++t)
    if (faces(t, 0) != faces(t, 1) && faces(t, 1) != faces(t, 2) && faces(t, 2) != faces(t, 0))
      proper.push_back(static_cast<int>(t));
  const Eigen::MatrixX3i F = faces(proper, Eigen::all);
  const MeshParts parts = mesh_parts(F, n);
  Eigen::MatrixX2d UV = Eigen::MatrixX2d::Zero(n, 2);
  std::vector<bool> fixed(n, false);
  for (int v = 0; v < n; ++v) fixed[v] = parts.part[v] < 0;

  std::vector<bool> part_done(parts.count, false);
  double offset = 0;
  for (const std::vector<int>& loop : numerics::boundary_loops(F)) {  // longest first
    const int k = parts.part[loop.front()];
    if (part_done[k]) continue;
    part_done[k] = true;
    const int m = static_cast<int>(loop.size());
    std::vector<double> arc(m + 1, 0);
    for (int i = 0; i < m; ++i) arc[i + 1] = arc[i] + (V.row(loop[(i + 1) % m]) - V.row(loop[i])).norm();
    const double length = arc[m];
    const double radius = length > 0 ? length / (2 * M_PI) : 1;
    for (int i = 0; i < m; ++i) {
      const double angle = 2 * M_PI * (length > 0 ? arc[i] / length : double(i) / m);
      UV.row(loop[i]) << offset + radius + radius * std::cos(angle), radius * std::sin(angle);
      fixed[loop[i]] = true;
    }
    offset += 2.2 * radius;
  }
  for (int k = 0; k < parts.count; ++k)
    if (!part_done[k])
      throw Error("tutte initialization needs a boundary, but the part with vertex " +
                  std::to_string(parts.first_vertex[k]) +
                  " is closed: cut it open, or use the asap initialization");

  std::vector<int> index(n, -1);
  int nfree = 0;
  for (int v = 0; v < n; ++v)
    if (!fixed[v]) index[v] = nfree++;
  if (nfree == 0) return UV;
  // Rows of the free vertices of −L = diag(W·1) − W, symmetric positive definite.
  const numerics::SparseMatrix W = numerics::uniform_weights(F, n);
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nfree, 2);
  for (int j = 0; j < W.outerSize(); ++j)
    for (numerics::SparseMatrix::InnerIterator it(W, j); it; ++it) {
      const int i = static_cast<int>(it.row());
      if (index[i] < 0 || i == j) continue;
      triplets.emplace_back(index[i], index[i], it.value());
      if (index[j] >= 0)
        triplets.emplace_back(index[i], index[j], -it.value());
      else
        rhs.row(index[i]) += it.value() * UV.row(j);
    }
  numerics::SparseMatrix A(nfree, nfree);
  A.setFromTriplets(triplets.begin(), triplets.end());
  numerics::SparseCholesky chol;
  chol.compute(A);
  const Eigen::MatrixXd x = chol.solve(rhs);
  for (int v = 0; v < n; ++v)
    if (index[v] >= 0) UV.row(v) = x.row(index[v]);
  return UV;
}

}  // namespace loom::arap
