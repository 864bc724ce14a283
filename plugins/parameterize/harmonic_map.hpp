// Maps with a fixed boundary: every free vertex is a weighted average of its
// neighbours, Σ_j w_ij (x_j - x_i) = 0, with the boundary vertices given.
// One sparse factorization serves all coordinates (two for UVs, three for a
// minimal surface).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "loom/numerics/boundary_map.hpp"
#include "loom/numerics/fixed_boundary.hpp"

namespace loom::parameterize {

using SparseMatrix = Eigen::SparseMatrix<double>;
// The shared pieces this plugin builds on (engine/numerics, also used by arap).
using numerics::BoundaryShape;
using numerics::FixedBoundarySolve;
using numerics::map_boundary;
using numerics::solve_fixed_boundary;
using numerics::square_corners;

enum class Weights {
  uniform,             // w_ij = 1 (Tutte 1963)
  cotangent,           // (cot α + cot β)/2 (Pinkall and Polthier 1993; harmonic, Eck et al. 1995)
  cotangent_clamped,   // max(cotangent, ε·mean |w|): positive, so never folds
  intrinsic_delaunay,  // cotangent weights of the intrinsic Delaunay triangulation
  mean_value,          // Floater 2003
  shape_preserving,    // Floater 1997
};
// In enum order, as the nodes spell them. A function, not a global: a node's
// declare() in another file may run during static initialization.
const std::vector<std::string>& weight_names();
Weights parse_weights(const std::string& name);

// W #V by #V, W(i,j) = w_ij; row i holds the weights of vertex i (symmetric
// except mean_value and shape_preserving).
//   V #V by 3, F #F by 3
SparseMatrix weight_matrix(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights);

// Floater's shape-preserving weights (Floater 1997, section 6): each free
// vertex's one-ring is flattened by a geodesic polar map (angles scaled to
// sum to 2π, lengths kept) and the vertex is written as the mean of its
// barycentric coordinates in the ring triangles that contain it. Rows of
// boundary vertices are empty.
SparseMatrix shape_preserving_weights(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

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
// connected pieces.
Parameterization parameterize(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights,
                              BoundaryShape shape);

// Interior vertices moved so that δ_i = Σ_j w_ij (x_j - x_i) = 0, all
// boundary loops fixed. With cotangent weights, `iterations` > 1 recomputes
// the weights on the new surface each time (Pinkall and Polthier 1993).
//   V #V by 3, F #F by 3; returns #V by 3
Eigen::MatrixX3d minimal_surface(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights,
                                 int iterations, FixedBoundarySolve* last = nullptr);

}  // namespace loom::parameterize
