#include "sphere_mesh.hpp"

#include <cmath>
#include <vector>

namespace loom::pathtrace {

std::shared_ptr<Mesh> sphere_mesh(const Eigen::Vector3d& center, double radius, int rings,
                                  int segments) {
  auto mesh = std::make_shared<Mesh>();
  const int n = (rings + 1) * (segments + 1);
  mesh->V.resize(n, 3);
  mesh->N.resize(n, 3);
  mesh->UV.resize(n, 2);
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
      const Eigen::Vector3d d(std::sin(theta) * std::cos(phi), std::cos(theta),
                              std::sin(theta) * std::sin(phi));
      const int i = r * (segments + 1) + s;
      mesh->V.row(i) = (center + radius * d).transpose();
      mesh->N.row(i) = d.transpose();
      mesh->UV.row(i) << double(s) / segments, 1 - double(r) / rings;
    }
  std::vector<Eigen::Vector3i> tris;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = r * (segments + 1) + s, b = a + segments + 1;
      // Counter-clockwise seen from outside; the poles' zero-area triangles are left out.
      if (r > 0) tris.emplace_back(a, a + 1, b);
      if (r < rings - 1) tris.emplace_back(a + 1, b + 1, b);
    }
  mesh->F.resize(Eigen::Index(tris.size()), 3);
  for (std::size_t i = 0; i < tris.size(); ++i) mesh->F.row(Eigen::Index(i)) = tris[i].transpose();
  return mesh;
}

}  // namespace loom::pathtrace
