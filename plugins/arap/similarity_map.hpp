// ASAP: the as-similar-as-possible parameterization (Liu et al. 2008, §4,
// eqs. 24–28), one sparse linear solve.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "mesh_parts.hpp"
#include "triangle_frames.hpp"

namespace loom::arap {

struct SimilarityMap {
  Eigen::MatrixX2d UV;   // #V by 2
  double energy = 0;     // the minimum of E below
  bool regularized = false;  // the system was singular (e.g. parts joined at a
                             // single vertex) and was solved with a 1e-8 diagonal shift
};

// Minimizes E(u, a, b) = ½ Σ_t Σ_i c_t^i ‖(u_t^i − u_t^{i+1}) − L_t d_t^i‖²,
// L_t = [a_t −b_t; b_t a_t], over u and every (a_t, b_t). For fixed u the
// optimal similarity is (a_t, b_t) = (P_t, Q_t) / C_t with C_t = Σ c ‖d‖²,
// P_t = Σ c d·e, Q_t = Σ c d×e (e = u^i − u^{i+1}); substituting it leaves the
// exact quadratic ½ Σ_t [Σ c ‖e‖² − (P_t² + Q_t²)/C_t] in u alone, a 2#V
// system solved by sparse Cholesky with the pins eliminated.
//   frames  of (V, F),  F #F by 3,  n = #V
//   pins    at least two per connected part (vertices of no face are held at 0)
//   check   optional, may throw to stop: called within the assembly and
//           between the factorization's steps
SimilarityMap similarity_map(const TriangleFrames& frames, const Eigen::MatrixX3i& F, int n,
                             const std::vector<Pin>& pins, const std::function<void()>& check = {});

// The pins ASAP needs: two per connected part, `given` (two vertex indices of
// one part) for its part and a far-apart pair for every other, laid along u at
// their distance in space, parts side by side. Throws loom::Error on a bad
// `given` (not two distinct vertices of one part).
//   V #V by 3, F #F by 3
std::vector<Pin> similarity_pins(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                 const std::vector<int>& given);

}  // namespace loom::arap
