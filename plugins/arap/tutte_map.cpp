#include "tutte_map.hpp"

#include <cmath>
#include <vector>

#include "loom/error.hpp"
#include "loom/numerics/boundary_map.hpp"
#include "loom/numerics/fixed_boundary.hpp"
#include "loom/numerics/laplacian.hpp"
#include "loom/numerics/mesh_topology.hpp"
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

  // Each part's longest loop on a circle by arc length (radius: loop length
  // over 2π, so UV scale matches 3D), parts side by side along u.
  std::vector<bool> part_done(parts.count, false);
  std::vector<int> fixed;
  for (int v = 0; v < n; ++v)
    if (parts.part[v] < 0) fixed.push_back(v);  // unreferenced: stays at (0, 0)
  double offset = 0;
  for (const std::vector<int>& loop : numerics::boundary_loops(F)) {  // longest first
    const int k = parts.part[loop.front()];
    if (part_done[k]) continue;
    part_done[k] = true;
    double length = 0;
    for (size_t i = 0; i < loop.size(); ++i) length += (V.row(loop[(i + 1) % loop.size()]) - V.row(loop[i])).norm();
    const double radius = length > 0 ? length / (2 * M_PI) : 1;
    const Eigen::MatrixX2d circle = numerics::map_boundary(V, F, loop, numerics::BoundaryShape::circle);
    for (size_t i = 0; i < loop.size(); ++i) {  // unit circle about (0.5, 0.5) -> radius about (offset + radius, 0)
      UV(loop[i], 0) = offset + radius + 2 * radius * (circle(i, 0) - 0.5);
      UV(loop[i], 1) = 2 * radius * (circle(i, 1) - 0.5);
      fixed.push_back(loop[i]);
    }
    offset += 2.2 * radius;
  }
  for (int k = 0; k < parts.count; ++k)
    if (!part_done[k])
      throw Error("tutte initialization needs a boundary, but the part with vertex " +
                  std::to_string(parts.first_vertex[k]) +
                  " is closed: cut it open, or use the asap initialization");

  // Tutte's uniform weights: every free vertex the average of its neighbours.
  return numerics::solve_fixed_boundary(numerics::uniform_weights(F, n), F, fixed, UV).X;
}

}  // namespace loom::arap
