// Connected parts of a triangle mesh and the pins each part needs: a
// flattening is defined up to a motion per part, so every part is pinned.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

namespace loom::arap {

// part  #V: index of the connected part (through shared vertices of faces)
//       of each vertex, −1 for a vertex no face references
struct MeshParts {
  std::vector<int> part;
  int count = 0;
  std::vector<int> first_vertex;  // count: the lowest vertex index of each part
};

// A vertex held at a fixed position in UV.
struct Pin {
  int vertex = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
};

//   F  #F by 3, n = #V
MeshParts mesh_parts(const Eigen::MatrixX3i& F, int n);

// Per part, two vertices far apart in space (a double sweep of farthest
// points: a lower bound of the diameter within a factor of 2).
//   V  #V by 3
std::vector<std::array<int, 2>> far_apart_pairs(const Eigen::MatrixX3d& V, const MeshParts& parts);

}  // namespace loom::arap
