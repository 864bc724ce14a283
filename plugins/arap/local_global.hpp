// ARAP parameterization by local/global iteration (Liu et al. 2008, §5),
// with the global system factored once.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "loom/numerics/sparse_solver.hpp"
#include "mesh_parts.hpp"
#include "triangle_frames.hpp"

namespace loom::arap {

// Everything that depends on the mesh and the pinned vertices only, so it is
// built once and reused by every iteration (and every run with other options).
// Global step: ∂E/∂u = 0 is K u = b(L) with the cotangent matrix
// K = Σ_t Σ_i c_t^i (e_i − e_{i+1})(e_i − e_{i+1})^T, constant, and
// b = Σ_t Σ_i c_t^i (e_i − e_{i+1}) (L_t d_t^i)^T.
struct ArapSystem {
  TriangleFrames frames;
  Eigen::MatrixX3i F;
  std::vector<int> free_index;   // #V: row of each free vertex in K_ff, −1 otherwise
  std::vector<int> free_vertex;  // #free: the inverse of free_index
  // Corners of each free vertex (3t + i), for a parallel gather of b.
  std::vector<int> corner_start, corners;
  numerics::SparseMatrix K_fp;   // #free by #V: the coupling to pinned vertices' columns
  numerics::SparseMatrix K;      // #free by #free: K_ff itself (what the benchmark times CHOLMOD on)
  numerics::SparseCholesky K_ff;
};

// pinned: vertices to hold (any may be given); every connected part without
// one gets its lowest vertex pinned; vertices no face references are held too.
// check (optional, may throw to stop) is called between the steps and within
// the long loops of the assembly and factorization.
//   V #V by 3, F #F by 3
ArapSystem arap_system(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                       std::vector<int> pinned, const std::function<void()>& check = {});

struct ArapOptions {
  int max_iterations = 100;
  double tolerance = 1e-6;  // stop when (E_k−1 − E_k) <= tolerance · E_k−1
  // < 0: pure ARAP, L_t the closest rotation. >= 0: the hybrid model, whose
  // energy adds ½ λ Σ_t (a_t² + b_t² − 1)² for L_t = [a −b; b a].
  double lambda = -1;
  // Anderson acceleration with this many past residuals (Peng et al. 2018),
  // with their energy safeguard: an extrapolated iterate that does not lower
  // E is replaced by the plain local/global step, so E still never increases.
  // 0: the plain iteration.
  int anderson = 5;
};

struct ArapResult {
  Eigen::MatrixX2d UV;          // #V by 2
  std::vector<double> energy;   // E of the initial map, then after each iteration
  int iterations = 0;
  bool converged = false;       // stopped by the tolerance, not the iteration cap
};

// E(u) = min_L ½ Σ_t Σ_i c_t^i ‖(u_t^i − u_t^{i+1}) − L_t d_t^i‖² (+ the hybrid
// term), which never increases from one iteration to the next.
//   UV0 #V by 2: the initial map; pinned vertices keep their rows.
//   after_iteration(k, E_k, u_k) is called after each iteration with its map
//   (may throw to stop).
ArapResult arap(const ArapSystem& system, const Eigen::MatrixX2d& UV0, const ArapOptions& options,
                const std::function<void(int, double, const Eigen::MatrixX2d&)>& after_iteration = {});

// The objective E(u) above that the local/global iterations minimize, with the
// best L_t per triangle (one local step): cotangent-weighted and not
// normalized, unlike numerics::DistortionReport::arap_energy (the area-weighted
// mean of (σ1-1)² + (σ2-1)²).
double local_global_energy(const TriangleFrames& frames, const Eigen::MatrixX3i& F, const Eigen::MatrixX2d& UV,
                           double lambda = -1);

}  // namespace loom::arap
