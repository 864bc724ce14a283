// Maps with a fixed boundary: every free vertex is a weighted average of its
// neighbours, Σ_j w_ij (x_j - x_i) = 0, with the boundary vertices given.
// One sparse factorization serves all coordinates (two for UVs, three for a
// minimal surface).
#pragma once

#include <functional>
#include <string>

#include <Eigen/Core>

#include "loom/numerics/boundary_map.hpp"
#include "loom/numerics/fixed_boundary.hpp"
#include "weights.hpp"

namespace loom::parameterize {

struct Parameterization {
  Eigen::MatrixX2d UV;             // #V by 2 in [0,1]²
  int boundary_vertices = 0;       // of the longest loop, the one mapped
  int holes_filled = 0;            // other loops, each closed by a fan for the solve
  int unreferenced = 0;            // vertices in no face: UV (0, 0)
  int uniform_rows = 0;
  std::string solver;
};

// Maps the longest boundary loop to the shape and the interior by the
// weights. Other boundary loops are filled (a fan to a new vertex at the
// loop's centroid) for the solve, so that the map stays one-to-one for
// positive weights, and dropped afterwards.
//   V #V by 3, F #F by 3
// Throws loom::Error for closed meshes, non-manifold edges, several
// connected pieces. `check` runs between the long stages (weights,
// assembly, factorization, solve): a node passes its cancellation check.
Parameterization parameterize(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights,
                              numerics::BoundaryShape shape, const std::function<void()>& check = {});

// Interior vertices moved so that δ_i = Σ_j w_ij (x_j - x_i) = 0, all
// boundary loops fixed. With cotangent weights, `iterations` > 1 recomputes
// the weights on the new surface each time (Pinkall and Polthier 1993).
//   V #V by 3, F #F by 3; returns #V by 3
Eigen::MatrixX3d minimal_surface(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights,
                                 int iterations, numerics::FixedBoundarySolve* last = nullptr);

}  // namespace loom::parameterize
