// Plugin author API. Fixed boundaries for a disk-topology map: a boundary loop placed on the
// unit circle or the unit square by arc length.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "loom/export.hpp"

namespace loom::numerics {

enum class BoundaryShape { circle, square };

// Places loop (vertex indices in boundary order, counter-clockwise as the
// faces see it) on the circle of centre (0.5, 0.5) and radius 0.5, starting
// at angle 0, or on the square [0,1]² with corners (0,0), (1,0), (1,1), (0,1);
// spacing is proportional to 3D edge length (arc length).
//   V     #V by 3 positions
//   F     #F by 3 triangles (the square's corners prefer ear tips, below)
//   loop  #B boundary vertex indices (#B >= 3, >= 4 for the square)
// Returns #B by 2 positions, row k for loop[k].
LOOM_API Eigen::MatrixX2d map_boundary(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                              const std::vector<int>& loop, BoundaryShape shape);

// The square's corners, as positions in loop (ascending). An ear tip (a
// boundary vertex whose two boundary edges share a face) inside a side would
// flatten its triangle to zero area, so with at most four ears every ear is
// a corner and the other corners split the longest remaining arcs at their
// arc-length middle (no ears: arc length 0, L/4, L/2, 3L/4 from loop[0]);
// with more, the start among the ears that puts the most of them on corners
// nearest to the quarter lengths.
LOOM_API std::vector<int> square_corners(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                const std::vector<int>& loop);

}  // namespace loom::numerics
