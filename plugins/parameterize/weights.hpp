// The edge weights w_ij of a fixed-boundary map: every free vertex becomes
// the weighted average of its neighbours, Σ_j w_ij (x_j - x_i) = 0.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace loom::parameterize {

enum class Weights {
  uniform,             // w_ij = 1 (Tutte 1963)
  cotangent,           // (cot α + cot β)/2 (Pinkall and Polthier 1993; harmonic, Eck et al. 1995)
  cotangent_clamped,   // max(cotangent, ε·mean |w|): positive, so never folds
  intrinsic_delaunay,  // cotangent weights of the intrinsic Delaunay triangulation
  mean_value,          // Floater 2003
  shape_preserving,    // Floater 1997
};
// Each value with its name as the nodes spell it, in enum order (a
// loom::EnumChoices<Weights>). A function, not a global: a node's declare() in
// another file may run during static initialization.
const std::vector<std::pair<Weights, std::string>>& weight_choices();
// The names alone, in enum order.
const std::vector<std::string>& weight_names();

// W #V by #V, W(i,j) = w_ij; row i holds the weights of vertex i (symmetric
// except mean_value and shape_preserving).
//   V #V by 3, F #F by 3
// check: a node's cancellation check (may throw), called within the
// cotangent and mean-value assemblies.
Eigen::SparseMatrix<double> weight_matrix(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, Weights weights,
                                          const std::function<void()>& check = {});

// Floater's shape-preserving weights (Floater 1997, section 6): each free
// vertex's one-ring is flattened by a geodesic polar map (angles scaled to
// sum to 2π, lengths kept) and the vertex is written as the mean of its
// barycentric coordinates in the ring triangles that contain it. Rows of
// boundary vertices are empty.
Eigen::SparseMatrix<double> shape_preserving_weights(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

}  // namespace loom::parameterize
