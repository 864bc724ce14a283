// One time step of a mass-spring system: forces, the implicit Euler solve (or
// symplectic Euler) and collisions. A frame is `substeps` of these.
//
// Damping: mass-proportional velocity damping, v_n ← e^{−c h} v_n before the
// step (exact decay of dv/dt = −c v), so it changes neither M nor the factored
// system. Wind: a linear drag on the normal relative velocity,
// f_i = a_i ((w_i − v_i)·n̂_i) n̂_i with a_i the vertex's area share and
// w_i = speed·ŵ·(1 + turbulence·η_i(t)), η a seeded sum of three travelling
// sine waves (smooth in space and time). Units: a_i in m², speeds in m/s,
// f_i in N, i.e. a drag coefficient of 1 N·s/m³ (kg m⁻² s⁻¹); real air's
// quadratic ½ ρ_air C_d |w|² (ρ_air = 1.2 kg/m³, C_d ≈ 1) matches it at 1.7 m/s
// and is 2.4 times stronger at 4 m/s. Colliders (ground plane y = height,
// spheres; inelastic, with optional Coulomb friction): Newton adds a penalty
// ½κ Σ d² over penetration depths to the potential, and friction as a
// lagged smoothed Coulomb potential in a second solve (normal forces κd from
// the first, frictionless one); local/global adds Projective Dynamics
// collision constraints ½ w ‖x_i − p_i‖² (p_i: x_i projected out of the
// colliders at each local step, with friction on that projection; w I in the
// prefactored matrix). Both project the result out, then the velocity is
// (x_{n+1} − x_n)/h with its component into the collider removed. Newton's
// report then holds both solves' iterations, each pass's residuals relative
// to its own start.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "implicit_solvers.hpp"
#include "mass_spring.hpp"

namespace loom::cloth {

enum class Solver { newton, local_global, explicit_euler };

// Where local/global's iteration starts. A truncated iteration stops short of
// the step's solution by an error that depends on the start:
//  prediction: y = x_n + h v_n + h² M⁻¹ f_ext. A cloth at rest restarts
//    h² M⁻¹ f_ext away from where it hangs every step and comes to rest off
//    its equilibrium.
//  extrapolation: x_n + h v_n. At rest it is x_n, and the equilibrium is an
//    exact fixed point of every step (the global step's right-hand side
//    there is M (y − x) − h² ∇V = 0); but what the iteration must add, h² g
//    and soft modes, comes slowly: with contact constraints (whose weight
//    is on every free vertex's diagonal) a falling cloth hardly falls.
//  lower_energy: whichever of the two has the lower E. Local/global never
//    raises E, so it starts from the better point by the measure it
//    minimizes: at an equilibrium x_n (E(x_n) = ½h⁴‖g‖²_M < E(y) ≈ h⁴‖g‖²_M),
//    in free fall y. Costs two evaluations of E per step.
// (Tried and dropped: the symplectic Euler position y + h² M⁻¹ f_int(x_n),
// also x_n at an equilibrium, amplifies the stiff springs' unbalanced force
// by h²k/m and set a resting curtain oscillating.)
// docs/cloth.md compares them at rest, in motion and in cost.
enum class Start { prediction, extrapolation, lower_energy };

struct Sphere {
  Eigen::Vector3d center;
  double radius;
};

struct StepSettings {
  Solver solver = Solver::local_global;
  SolveOptions solve;
  Start start = Start::lower_energy;  // local/global only
  Eigen::Vector3d gravity{0, -9.81, 0};
  double damping = 0;  // c in 1/s
  Eigen::Vector3d wind_direction{0, 0, 1};
  double wind_speed = 0;
  double turbulence = 0;
  std::uint64_t seed = 1;
  bool ground = false;
  double ground_height = 0;
  std::vector<Sphere> spheres;
  double friction = 0;  // Coulomb coefficient μ
};

struct ClothState {
  std::shared_ptr<const SpringSystem> system;
  Eigen::MatrixX3d x, v;
  double time = 0;  // seconds simulated
};

// The initial state: at rest in the system's positions.
ClothState rest_state(std::shared_ptr<const SpringSystem> system);

// ω_max estimate for explicit stability: sqrt(max_i 2 Σ_{s∋i} k_s / m_i)
// (Gershgorin's bound on M⁻¹K); symplectic Euler is stable for h ω_max < 2.
double max_frequency(const SpringSystem& s);

struct StepResult {
  ClothState state;
  SolveReport report;
};

// Advances by h. `lg` is the local/global solver factored for this system and
// h (required for Solver::local_global, see cached_solver in the node).
// `newton_workspace`: Newton's Hessian and factorization, kept across the steps of
// one system so its pattern and symbolic analysis are made once (nullptr: per step).
// Throws loom::Error if explicit integration diverges (non-finite positions).
StepResult step(const ClothState& state, double h, const StepSettings& settings, const LocalGlobalSolver* lg,
                NewtonWorkspace* newton_workspace = nullptr);

// y = x_n + h v_n + h² M⁻¹ f_ext, the step's inertial prediction (v_n after
// damping; fixed rows at x_n): E's target, and where Newton starts.
Eigen::MatrixX3d inertial_prediction(const ClothState& state, double h, const StepSettings& settings);

// The weight w of local/global's contact constraints (Projective Dynamics):
// 0.1 × the stiffest spring's k (measured on the drape, docs/cloth.md: a
// weight of k leaves 9 % stretch at rest against 3 % at 0.1 k; below that
// no change; its diagonal h² w slows the free vertices' convergence).
double contact_weight(const SpringSystem& s);

// External forces at (x, v, t): gravity m g plus wind; #V by 3.
Eigen::MatrixX3d external_forces(const SpringSystem& s, const Eigen::MatrixX3d& x,
                                 const Eigen::MatrixX3d& v, double t, const StepSettings& settings);

}  // namespace loom::cloth
