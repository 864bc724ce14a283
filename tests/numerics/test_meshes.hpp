// Small meshes built in code for the numerics tests.
//   V #V by 3, F #F by 3 (counter-clockwise seen from +z for the planar ones)
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>

namespace loom::numerics::test {

struct TestMesh {
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
};

// A (nx+1) by (ny+1) grid of the unit square, each cell split in two; cells
// where keep(i, j) is false are left out (holes).
template <class Keep>
TestMesh grid(int nx, int ny, Keep keep) {
  TestMesh m;
  m.V.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.V.row(j * (nx + 1) + i) << double(i) / nx, double(j) / ny, 0;
  std::vector<Eigen::Vector3i> faces;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (!keep(i, j)) continue;
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      faces.emplace_back(a, b, d);
      faces.emplace_back(a, d, c);
    }
  m.F.resize(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) m.F.row(f) = faces[f].transpose();
  return m;
}

inline TestMesh grid(int nx, int ny) {
  return grid(nx, ny, [](int, int) { return true; });
}

// Concentric rings r = inner + (1 - inner)·k/rings, `segments` vertices each;
// inner = 0 gives a disk with a centre vertex, inner > 0 an annulus.
inline TestMesh disk(int rings, int segments, double inner = 0) {
  TestMesh m;
  const int first = inner > 0 ? 0 : 1;
  const int n = (inner > 0 ? 0 : 1) + (rings + 1 - first) * segments;
  m.V.resize(n, 3);
  int v = 0;
  if (inner == 0) m.V.row(v++) << 0, 0, 0;
  for (int k = first; k <= rings; ++k)
    for (int s = 0; s < segments; ++s) {
      const double r = inner + (1 - inner) * k / rings, t = 2 * M_PI * s / segments;
      m.V.row(v++) << r * std::cos(t), r * std::sin(t), 0;
    }
  auto at = [&](int k, int s) { return (inner == 0 ? 1 : 0) + (k - first) * segments + (s % segments); };
  std::vector<Eigen::Vector3i> faces;
  if (inner == 0)
    for (int s = 0; s < segments; ++s) faces.emplace_back(0, at(1, s), at(1, s + 1));
  for (int k = first; k < rings; ++k)
    for (int s = 0; s < segments; ++s) {
      faces.emplace_back(at(k, s), at(k + 1, s), at(k + 1, s + 1));
      faces.emplace_back(at(k, s), at(k + 1, s + 1), at(k, s + 1));
    }
  m.F.resize(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) m.F.row(f) = faces[f].transpose();
  return m;
}

}  // namespace loom::numerics::test
