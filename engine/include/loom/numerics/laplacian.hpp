// Plugin author API. Discrete Laplacians as sparse weight matrices.
//
// Each returns W, #V by #V, W(i,j) = w_ij for each edge (i,j), zero diagonal.
// The Laplacian is L = W - diag(W·1) (negative semi-definite when w_ij >= 0),
// so δ_i = Σ_j w_ij (x_j - x_i). Solvers build the rows they need from W.
//
//   V  #V by 3 positions    F  #F by 3 triangles
//   check  (where taken) called every 65536 faces and within the assembly;
//          a node's cancellation check, may throw to stop
#pragma once

#include <functional>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "loom/export.hpp"

namespace loom::numerics {

using SparseMatrix = Eigen::SparseMatrix<double>;

// w_ij = 1 for each edge (Tutte).
LOOM_API SparseMatrix uniform_weights(const Eigen::MatrixX3i& F, int n);

// w_ij = (cot α_ij + cot β_ij) / 2, the angles opposite edge (i,j) (Pinkall and
// Polthier 1993). Negative on obtuse triangles. Degenerate (zero-area)
// triangles contribute nothing instead of infinities.
LOOM_API SparseMatrix cotangent_weights(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                       const std::function<void()>& check = {});

// Cotangent weights of the intrinsic Delaunay triangulation (Bobenko and
// Springborn 2007): the mesh's edges are flipped, on their lengths alone,
// until every interior edge is locally Delaunay, and W holds the cotangent
// weights of that triangulation. Its edges may join vertices that are not
// mesh neighbours (W then has nonzeros off the mesh's edges), which is fine
// for a solve. Every weight on an interior edge is >= 0, so every row of an
// interior vertex is a convex combination; weights of boundary edges (which
// cannot flip) keep their sign. The robust choice for harmonic maps.
LOOM_API SparseMatrix intrinsic_delaunay_cotangent_weights(const Eigen::MatrixX3d& V,
                                                           const Eigen::MatrixX3i& F);

// w_ij = (tan(α_ij/2) + tan(β_ij/2)) / |x_i - x_j| (Floater 2003): positive, not
// symmetric (row i belongs to vertex i).
LOOM_API SparseMatrix mean_value_weights(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                        const std::function<void()>& check = {});

}  // namespace loom::numerics
