// Plugin author API. Combinatorial mesh operators on F (#F by 3 triangle indices into #V vertices).
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "loom/export.hpp"

namespace loom::numerics {

// Boundary loops, each an ordered list of vertex indices following the
// boundary edges' orientation; sorted longest first (by edge count).
// Throws loom::Error on a non-manifold edge (used by more than two faces),
// naming the edge. check (optional, may throw to stop) is called between the
// steps: a node's cancellation check.
LOOM_API std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixX3i& F,
                                                      const std::function<void()>& check = {});

// For each vertex, its neighbours (sorted, no duplicates). n = #V.
LOOM_API std::vector<std::vector<int>> vertex_adjacency(const Eigen::MatrixX3i& F, int n);

// Connected components through shared vertices of faces: for each of the n
// vertices its component, numbered 0.. in order of each component's lowest
// vertex, or -1 for a vertex no face references. *count (if given) receives
// the number of components. One union-find for every caller.
LOOM_API std::vector<int> connected_components(const Eigen::MatrixX3i& F, int n, int* count = nullptr);

// Vertices referenced by at least one face.
LOOM_API std::vector<bool> referenced_vertices(const Eigen::MatrixX3i& F, int n);

}  // namespace loom::numerics
