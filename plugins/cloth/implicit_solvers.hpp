// Two ways to minimize the incremental potential E of one implicit Euler step
// (incremental_potential.hpp), both from a start x0 whose fixed rows stay put.
//
// newton_solve: Newton's method on g(x) = ∇E(x) = 0 with the assembled
//   symmetric sparse Hessian (assignment eq. (38)), per spring
//     H_s = k [ r̂r̂ᵀ + max(0, 1 − l/‖r‖)(I − r̂r̂ᵀ) ],
//   i.e. the l/‖r‖ − 1 term clamped where a spring is compressed (‖r‖ < l),
//   which makes every block, hence M + h² Σ H_s, positive definite. Each
//   direction is a CHOLMOD solve, then a backtracking (Armijo) line search on
//   E. The Hessian's pattern never changes (contact blocks fall on the
//   diagonal blocks every free vertex has), so a caller that passes the same
//   NewtonWorkspace for every step builds the pattern and pays the symbolic
//   analysis (ordering, supernodes) once; each iteration is then a refill of
//   the values and a numeric refactorization.
// LocalGlobalSolver: Liu, Bargteil, O'Brien, Kavan 2013. Local step (eq. 12):
//   d_s = l_s r_s/‖r_s‖ per spring; global step (eq. 10/14):
//   (M + h² L) x = h² J d + M y, M + h² L factored once per (springs, k, h,
//   masses, fixed set): an iteration costs one back-substitution for x, y, z.
//   Optional Chebyshev semi-iterative acceleration (Wang 2015, eq. 9-10)
//   after 4 plain iterations, with a given estimate ρ of the plain
//   iteration's spectral radius (0.99 suits cloth at k = 1e5, h = 1/30).
//   Or Anderson acceleration (Peng et al. 2018, loom/numerics/anderson.hpp)
//   of the map x_k ↦ x_{k+1} over the last m iterations, safeguarded by the
//   energy E the iteration lowers (below): an extrapolated iterate whose E is
//   not below the last accepted one is replaced by the plain step, and the
//   history starts again.
//
// Residual: ‖∇E(x_k)‖ / ‖∇E(x0)‖ after each iteration (the same measure for
// both, so they are compared on one scale); tolerance 0 runs every iteration.
#pragma once

#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "loom/numerics/sparse_solver.hpp"
#include "mass_spring.hpp"

namespace loom::cloth {

struct SolveOptions {
  int iterations = 10;
  double tolerance = 0;
  bool record_residuals = true;  // local/global: skip the gradient when false and tolerance is 0
  bool chebyshev = false;        // local/global only
  double chebyshev_rho = 0.99;   // spectral radius of the plain iteration, in (0, 1)
  // Local/global only, not with chebyshev: Anderson's window m (0: off).
  int anderson = 0;
  // Called on every iterate (e.g. to push positions out of colliders); empty:
  // nothing. It makes the iteration a projected one, so the residual then
  // measures the unconstrained gradient and no longer reaches zero.
  std::function<void(Eigen::MatrixX3d&)> project;
  // Local/global with a contact weight w > 0 (Projective Dynamics, Bouaziz et
  // al. 2014, collision constraints): the projection of an iterate x onto the
  // collider-free set (x itself where a vertex is outside). The solver adds
  // ½ w Σ_i ‖x_i − p_i‖² to E, p_i the projection at the iteration's local
  // step; the weight's diagonal h² w I is in the prefactored matrix. The
  // residual still measures the springs' E only, so with contacts it no
  // longer reaches zero (a tolerance then rarely stops the iterations).
  std::function<void(const Eigen::MatrixX3d& x, Eigen::MatrixX3d& target)> contact_target;
  // Called after every iteration from the calling thread (the node checks
  // cancellation there); may throw to stop.
  std::function<void()> after_iteration;
  // Newton only: called from the calling thread within an iteration's long
  // steps (the Hessian's assembly, between the factorization's phases, each
  // line-search trial), the node's cancellation check; may throw to stop.
  std::function<void()> check;
  // Newton only: a penalty potential P(x) added to the springs' (E gains
  // h² P). Returns P and adds ∇P to *gradient and (vertex, 3x3 block) pairs
  // of a positive semidefinite Hessian approximation to *blocks.
  std::function<double(const Eigen::MatrixX3d& x, Eigen::MatrixX3d* gradient,
                       std::vector<std::pair<int, Eigen::Matrix3d>>* blocks)>
      penalty;
};

struct SolveReport {
  std::vector<double> residuals;
  // ‖∇E(x0)‖, the scale `residuals` are relative to (0 when not measured):
  // with it a caller puts solves from different starts on one scale.
  double start_gradient = 0;
  // Local/global with Anderson: the E (springs, inertia and contact
  // constraints) of the start, then of each accepted iterate (the start's
  // plus the accepted changes, each computed without cancellation).
  std::vector<double> energies;
  int rejected = 0;  // Anderson iterates the safeguard replaced by the plain step
  int iterations = 0;
  bool converged = false;
};

// Newton's matrix M + h² Σ_s H_s (+ h² the penalty's blocks) over the free
// unknowns (3 per free vertex, in vertex order), and what Newton keeps across
// the calls for one system: the matrix's storage and the factor's symbolic
// analysis. The pattern (every spring's four 3×3 blocks and every free
// vertex's diagonal block) depends only on the springs and the fixed set; it
// is built at the first assembly, and every later one refills the values in
// place, adding the same terms in the same order as a sum of triplets would
// (mass, springs in order, penalty), so the matrix is the same bit for bit.
// A workspace serves one system: give another system a fresh one.
class NewtonWorkspace {
 public:
  // Builds the pattern for s unless it is built for the same springs and fixed set.
  void prepare(const SpringSystem& s);
  // Unknown row (the first of 3) of each vertex, −1 if fixed; after prepare.
  const std::vector<int>& rows() const { return row_; }
  int unknowns() const { return static_cast<int>(matrix_.rows()); }
  // Assembles the matrix at x (after prepare); calls options.check between
  // chunks of springs and options.penalty for the contact blocks.
  const loom::numerics::SparseMatrix& hessian(const SpringSystem& s, const Eigen::MatrixX3d& x, double h,
                                              const SolveOptions& options);
  loom::numerics::SparseCholesky& factor() { return factor_; }

 private:
  // Adds scale·b to the 3×3 block whose (0, 0) entry is values[at], in a
  // column block of `stride` entries per column.
  void add_block(int at, int stride, const Eigen::Matrix3d& b, double scale);
  Eigen::MatrixX2i springs_;  // the system the pattern is for
  Eigen::VectorXi fixed_;
  loom::numerics::SparseMatrix matrix_;
  std::vector<int> row_;
  std::vector<int> stride_;       // per free vertex: entries in each of its three columns
  std::vector<int> diagonal_at_;  // per free vertex: its diagonal block's (0, 0) entry
  std::vector<int> spring_at_;    // per spring and (p, q): the block (p's rows, q's columns), −1: none
  loom::numerics::SparseCholesky factor_;
};

// `workspace`: kept across calls for one system (nullptr: a fresh one, built
// and analysed on the first iteration).
Eigen::MatrixX3d newton_solve(const SpringSystem& s, const Eigen::MatrixX3d& y, double h, Eigen::MatrixX3d x0,
                              const SolveOptions& options, SolveReport* report = nullptr,
                              NewtonWorkspace* workspace = nullptr);

class LocalGlobalSolver {
 public:
  // Factors M_ff + h² L_ff over the free vertices (throws loom::Error when
  // the system is not positive definite, which a positive mass rules out).
  // `contact_weight` w ≥ 0: h² w I joins the matrix (the contact
  // constraints' diagonal, used with SolveOptions::contact_target).
  LocalGlobalSolver(const SpringSystem& s, double h, double contact_weight = 0);
  Eigen::MatrixX3d solve(const SpringSystem& s, const Eigen::MatrixX3d& y, Eigen::MatrixX3d x0,
                         const SolveOptions& options, SolveReport* report = nullptr) const;
  double h() const { return h_; }
  double contact_weight() const { return contact_weight_; }
  int free_vertices() const { return static_cast<int>(free_.size()); }

 private:
  // Local step at x (eq. 12): the springs' r_s − d_s into `excess` and, with
  // contacts, the projections p_i into `target`. With `energy`: returns
  //   E(x) = ½ ‖x − y‖²_M + h² (Σ_s ½ k_s ‖r_s − d_s‖² + ½ w Σ_i ‖x_i − p_i‖²),
  // the objective local/global minimizes (‖r_s − d_s‖ = |‖r_s‖ − l_s|); else 0.
  double local_step(const SpringSystem& s, const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y,
                    const SolveOptions& options, bool energy, Eigen::MatrixX3d& excess,
                    Eigen::MatrixX3d& target) const;
  // E(b) − E(a) for E above, accurate to rounding relative to the change;
  // target_a, target_b: the contact projections at a and b (nullptr: none).
  double energy_change(const SpringSystem& s, const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b,
                       const Eigen::MatrixX3d& y, const Eigen::MatrixX3d* target_a,
                       const Eigen::MatrixX3d* target_b) const;
  // Global step (eq. 10): Δ = x_{k+1} − x_k over the free rows, #free by 3.
  Eigen::MatrixXd global_step(const SpringSystem& s, const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y,
                              const Eigen::MatrixX3d& excess, const Eigen::MatrixX3d* target) const;
  double h_;
  double contact_weight_;
  std::vector<int> free_;   // free vertex of each unknown row
  std::vector<int> row_;    // unknown row of each vertex, −1 if fixed
  // Factored once, solved every iteration: kept simplicial (no BLAS per solve).
  loom::numerics::SparseCholesky cholesky_{loom::numerics::SparseCholesky::Options{true}};
};

}  // namespace loom::cloth
