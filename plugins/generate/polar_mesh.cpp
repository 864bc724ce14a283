#include "polar_mesh.hpp"

#include <cmath>

namespace loom::generate {

void require_polar_counts(int rings, int segments) {
  if (rings < 1) throw Error("rings must be at least 1");
  if (segments < 3) throw Error("segments must be at least 3");
  // Each declared range alone is reasonable; their product may not be (4096
  // rings of 65536 segments is 268M vertices, 6 GB of faces).
  constexpr long long kMaxVertices = 1LL << 24;
  const long long n = static_cast<long long>(rings) * segments;
  if (n > kMaxVertices)
    throw Error("rings × segments = " + std::to_string(n) + " vertices: more than the " +
                std::to_string(kMaxVertices) + " a generated mesh may have");
}

Mesh polar_mesh(int rings, int segments, const std::function<Eigen::Vector3d(double, double)>& position) {
  require_polar_counts(rings, segments);
  Mesh mesh;
  mesh.V.resize(1 + rings * segments, 3);
  mesh.F.resize(segments * (2 * rings - 1), 3);
  mesh.V.row(0) = position(0.0, 0.0);
  auto index = [&](int ring, int s) { return 1 + (ring - 1) * segments + (s % segments); };
  for (int r = 1; r <= rings; ++r)
    for (int s = 0; s < segments; ++s)
      mesh.V.row(index(r, s)) = position(static_cast<double>(r) / rings, 2 * M_PI * s / segments);
  int f = 0;
  for (int s = 0; s < segments; ++s) mesh.F.row(f++) << 0, index(1, s), index(1, s + 1);
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      mesh.F.row(f++) << index(r, s), index(r + 1, s), index(r + 1, s + 1);
      mesh.F.row(f++) << index(r, s), index(r + 1, s + 1), index(r, s + 1);
    }
  return mesh;
}

}  // namespace loom::generate
