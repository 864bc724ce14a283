// Meshes on a polar grid: a pole vertex, then `rings` rings of `segments`
// vertices each. position(t, phi) gives the vertex at radial parameter
// t in (0, 1] (ring k has t = k / rings) and angle phi; the pole is
// position(0, 0). Triangles are counter-clockwise seen from +z (outside).
#pragma once

#include <functional>

#include "loom/mesh.hpp"

namespace loom::generate {

Mesh polar_mesh(int rings, int segments, const std::function<Eigen::Vector3d(double, double)>& position);

// Validates ring and segment counts with a message naming the input, and
// their product (at most 2^24 vertices).
void require_polar_counts(int rings, int segments);

}  // namespace loom::generate
