// A latitude-longitude sphere mesh with outward vertex normals (+y is the
// pole axis), shared by the Cornell box, the tests and the benchmark.
#pragma once

#include <memory>

#include "loom/mesh.hpp"

namespace loom::pathtrace {

std::shared_ptr<Mesh> sphere_mesh(const Eigen::Vector3d& center, double radius, int rings,
                                  int segments);

}  // namespace loom::pathtrace
