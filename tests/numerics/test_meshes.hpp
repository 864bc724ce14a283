// Small meshes built in code for the numerics tests, from the generate
// plugin's library (loom_generate_core) where it has the shape.
//   V #V by 3, F #F by 3 (counter-clockwise seen from +z for the planar ones)
#pragma once

#include <cmath>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "generators.hpp"

namespace loom::numerics::test {

using TestMesh = Mesh;

// A (nx+1) by (ny+1) grid of the unit square, each cell split in two; cells
// where keep(i, j) is false are left out (holes).
inline TestMesh grid(int nx, int ny, const std::function<bool(int, int)>& keep = {}) {
  return generate::grid_mesh(nx, ny, [](double u, double v) { return Eigen::Vector3d(u, v, 0); }, keep);
}

// The unit disk in z = 0 on a polar grid: a centre vertex, then rings
// r = k/rings of `segments` vertices each.
inline TestMesh disk(int rings, int segments) {
  return generate::polar_mesh(rings, segments, [](double r, double phi) {
    return Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), 0);
  });
}

// An annulus: rings + 1 concentric rings r = inner + (1 - inner)·k/rings,
// k = 0..rings, of `segments` vertices each (inner > 0).
inline TestMesh annulus(int rings, int segments, double inner) {
  TestMesh m;
  m.V.resize((rings + 1) * segments, 3);
  int v = 0;
  for (int k = 0; k <= rings; ++k)
    for (int s = 0; s < segments; ++s) {
      const double r = inner + (1 - inner) * k / rings, t = 2 * M_PI * s / segments;
      m.V.row(v++) << r * std::cos(t), r * std::sin(t), 0;
    }
  auto at = [&](int k, int s) { return k * segments + (s % segments); };
  std::vector<Eigen::Vector3i> faces;
  for (int k = 0; k < rings; ++k)
    for (int s = 0; s < segments; ++s) {
      faces.emplace_back(at(k, s), at(k + 1, s), at(k + 1, s + 1));
      faces.emplace_back(at(k, s), at(k + 1, s + 1), at(k, s + 1));
    }
  m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) m.F.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
  return m;
}

}  // namespace loom::numerics::test
