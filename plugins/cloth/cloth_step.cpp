// ClothStep: the simulation step, state at frame f−1 → state at frame f, by
// implicit Euler (Newton or Liu 2013 local/global) or symplectic Euler.
#include <cmath>
#include <memory>
#include <string>

#include "cloth_state.hpp"
#include "loom/hash.hpp"
#include "loom/plugin.hpp"
#include "time_step.hpp"

namespace {

using loom::cloth::Solver;

// The local/global factorization depends on the springs, their k, the masses,
// the fixed set, h and the contact weight (with colliders) only: one per
// (system, h, colliders or not), kept across frames.
std::shared_ptr<loom::cloth::LocalGlobalSolver> cached_solver(loom::Context& ctx,
                                                              const loom::cloth::SpringSystem& s,
                                                              double h, double contact_weight) {
  loom::Hasher key;
  key.bytes(s.springs.data(), sizeof(int) * s.springs.size())
      .bytes(s.stiffness.data(), sizeof(double) * s.stiffness.size())
      .bytes(s.mass.data(), sizeof(double) * s.mass.size())
      .bytes(s.fixed.data(), sizeof(int) * s.fixed.size())
      .pod(h)
      .pod(contact_weight);
  return ctx.scratch<loom::cloth::LocalGlobalSolver>(key.digest(), [&] {
    return std::make_shared<loom::cloth::LocalGlobalSolver>(s, h, contact_weight);
  });
}

struct ClothStep {
  static constexpr const char* name = "ClothStep";
  static void declare(loom::NodeSpec& s) {
    s.describe("Advances a mass-spring system by one frame (1/fps, in substeps): implicit Euler by "
               "Newton's method (clamped sparse Hessian, line search, CHOLMOD) or by Liu et al. "
               "2013's local/global iteration (M + h²L factored once, optional Chebyshev or "
               "Anderson acceleration), or symplectic Euler. Gravity, velocity damping, wind, ground and "
               "sphere colliders.")
        .input<loom::cloth::ClothState>("state", "the state at the previous frame (at the start "
                                                 "frame: the initial state, returned unchanged)")
        .enum_input("solver", Solver::local_global,
                    {{Solver::local_global, "local_global"},
                     {Solver::newton, "newton"},
                     {Solver::explicit_euler, "explicit"}},
                    "how each substep is solved")
        .input<int>("substeps", 1, "time steps per frame: h = 1/(fps·substeps)").range(1, 100000)
        .input<int>("iterations", 10, "maximal solver iterations per substep").range(1, 1000000)
        .input<double>("tolerance", 0,
                       "stop when ‖∇E‖ falls below this fraction of its start (0: always run every iteration)")
        .at_least(0)
        .input<loom::Vec3>("gravity", loom::Vec3(0, -9.81, 0), "gravitational acceleration in m/s²")
        .input<double>("damping", 0, "velocity damping rate c in 1/s: v ← e^{−ch} v each substep").at_least(0)
        .input<loom::Vec3>("wind_direction", loom::Vec3(0, 0, 1), "direction the wind blows to")
        .input<double>("wind_speed", 0,
                       "wind speed in m/s; the drag on a vertex is its area (m²) times the normal relative "
                       "speed (m/s) along its normal, in N: a coefficient of 1 N·s/m³")
        .at_least(0)
        .input<double>("turbulence", 0.5, "relative amplitude of the seeded wind gusts").range(0, 10)
        .input<bool>("ground", false, "a ground plane y = ground_height the cloth cannot pass")
        .input<double>("ground_height", 0, "height of the ground plane")
        .input<std::vector<loom::Vec3>>("sphere_centers", {}, "centers of sphere colliders")
        .input<std::vector<double>>("sphere_radii", {}, "radii of sphere colliders, one per center")
        .input<double>("friction", 0, "Coulomb friction coefficient of the colliders (0: frictionless)").range(0, 10)
        .input<bool>("chebyshev", false, "Chebyshev acceleration of local/global (Wang 2015)")
        .input<double>("chebyshev_rho", 0.99, "estimated spectral radius for Chebyshev").range(0, 0.9999)
        .input<int>("anderson", 0,
                    "Anderson acceleration of local/global over this many past iterates (Peng et al. 2018; "
                    "0: off), with an energy safeguard that falls back to the plain step")
        .range(0, 50)
        .output<loom::cloth::ClothState>("state", "the state at this frame")
        .output<loom::Mesh>("mesh", "the deformed surface at this frame")
        .output<std::vector<double>>("residuals",
                                     "‖∇E‖ relative to its start after each iteration of the "
                                     "frame's last substep (empty for explicit)")
        .set_simulation("state", "state");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const auto previous = in.share<loom::cloth::ClothState>("state");
    const loom::cloth::SpringSystem& system = *previous->system;
    loom::cloth::StepSettings settings;
    settings.solver = in.get<Solver>("solver");
    settings.solve.iterations = in.get<int>("iterations");
    settings.solve.tolerance = in.get<double>("tolerance");
    settings.solve.chebyshev = in.get<bool>("chebyshev");
    settings.solve.chebyshev_rho = in.get<double>("chebyshev_rho");
    settings.solve.anderson = in.get<int>("anderson");
    if (settings.solve.chebyshev && settings.solve.anderson > 0)
      throw loom::Error("chebyshev and anderson both accelerate local/global: set anderson to 0 or chebyshev to false");
    settings.solve.after_iteration = [&ctx] { ctx.check_cancelled(); };
    settings.solve.check = settings.solve.after_iteration;
    settings.gravity = in.get<loom::Vec3>("gravity");
    settings.damping = in.get<double>("damping");
    settings.wind_direction = in.get<loom::Vec3>("wind_direction");
    settings.wind_speed = in.get<double>("wind_speed");
    settings.turbulence = in.get<double>("turbulence");
    settings.seed = ctx.seed();
    settings.ground = in.get<bool>("ground");
    settings.ground_height = in.get<double>("ground_height");
    settings.friction = in.get<double>("friction");
    const auto& centers = in.get<std::vector<loom::Vec3>>("sphere_centers");
    const auto& radii = in.get<std::vector<double>>("sphere_radii");
    if (centers.size() != radii.size())
      throw loom::Error("sphere_centers has " + std::to_string(centers.size()) + " entries but sphere_radii has " +
                        std::to_string(radii.size()) + ": give one radius per center");
    for (size_t i = 0; i < centers.size(); ++i) {
      if (!(radii[i] > 0) || !std::isfinite(radii[i]) || !centers[i].allFinite())
        throw loom::Error("sphere " + std::to_string(i) + " needs a finite center and a positive radius");
      settings.spheres.push_back({centers[i], radii[i]});
    }

    const double frame_step = ctx.time().step;
    if (frame_step == 0) {  // the start frame: the initial state itself
      out.set("mesh", loom::cloth::state_mesh(*previous));
      out.set("residuals", std::vector<double>{});
      out.share("state", previous);
      return;
    }
    const int substeps = in.get<int>("substeps");
    const double h = frame_step / substeps;
    std::shared_ptr<loom::cloth::LocalGlobalSolver> lg;
    if (settings.solver == Solver::local_global) {
      ctx.progress(0, substeps, "factoring");
      const bool colliders = settings.ground || !settings.spheres.empty();
      lg = cached_solver(ctx, system, h, colliders ? loom::cloth::contact_weight(system) : 0.0);
    }
    if (settings.solver == Solver::explicit_euler) {
      const double bound = 2 / loom::cloth::max_frequency(system);
      if (h > bound)
        ctx.warn("explicit: h = " + std::to_string(h) + " s exceeds the stability bound 2/ω_max = " +
                 std::to_string(bound) + " s (ω_max from the largest k/m); it will blow up: use at least " +
                 std::to_string(static_cast<long long>(std::ceil(frame_step / bound))) +
                 " substeps or an implicit solver");
    }
    // Newton: one symbolic analysis per frame, shared by its substeps.
    loom::cloth::NewtonWorkspace newton_workspace;
    loom::cloth::StepResult result{*previous, {}};
    for (int k = 0; k < substeps; ++k) {
      ctx.progress(k, substeps, "substeps");
      ctx.check_cancelled();
      result = loom::cloth::step(result.state, h, settings, lg.get(), &newton_workspace);
    }
    out.set("mesh", loom::cloth::state_mesh(result.state));
    out.set("residuals", result.report.residuals);
    out.set("state", std::move(result.state));
  }
};
LOOM_NODE(ClothStep);

}  // namespace
