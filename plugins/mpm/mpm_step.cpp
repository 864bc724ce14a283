// MPMStep: the MLS-MPM simulation step, state(f − 1) → state(f), substeps by a
// CFL rule inside.
#include <string>

#include "loom/error.hpp"
#include "loom/plugin.hpp"
#include "loom/point_set.hpp"
#include "mls_mpm.hpp"
#include "mpm_state.hpp"

namespace {

using namespace loom::mpm;

// The domain walls: a Boundary, or none.
enum class Walls { sticky, slip, separate, open };

// A collider's "boundary" field.
Boundary boundary_from(const std::string& name) {
  if (name == "sticky") return Boundary::sticky;
  if (name == "slip") return Boundary::slip;
  if (name == "separate") return Boundary::separate;
  throw loom::Error("unknown boundary '" + name + "' (sticky, slip or separate)");
}

loom::Vec3 vec3(const loom::json& j, const char* key, int index) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3)
    throw loom::Error("colliders[" + std::to_string(index) + "]." + key +
                      " must be a list of 3 numbers");
  loom::Vec3 v;
  for (int d = 0; d < 3; ++d) v[d] = j[key][static_cast<std::size_t>(d)].get<double>();
  return v;
}

// [{"shape": "plane", "point": [x, y, z], "normal": [x, y, z], "boundary": "slip"},
//  {"shape": "sphere", "center": [x, y, z], "radius": r, "boundary": "sticky"}]
std::vector<Collider> colliders_from(const loom::json& list) {
  if (!list.is_array()) throw loom::Error("colliders must be a list of objects");
  std::vector<Collider> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const loom::json& j = list[i];
    const int k = static_cast<int>(i);
    if (!j.is_object() || !j.contains("shape"))
      throw loom::Error("colliders[" + std::to_string(i) + "] needs a \"shape\" (plane or sphere)");
    Collider c;
    c.boundary = boundary_from(j.value("boundary", std::string("slip")));
    const std::string shape = j["shape"].get<std::string>();
    if (shape == "plane") {
      c.shape = Collider::Shape::plane;
      c.point = vec3(j, "point", k);
      c.normal = vec3(j, "normal", k);
      if (!(c.normal.norm() > 0)) throw loom::Error("colliders[" + std::to_string(i) + "].normal is zero");
      c.normal.normalize();
    } else if (shape == "sphere") {
      c.shape = Collider::Shape::sphere;
      c.point = vec3(j, "center", k);
      c.radius = j.value("radius", 0.0);
      if (!(c.radius > 0)) throw loom::Error("colliders[" + std::to_string(i) + "].radius must be positive");
    } else {
      throw loom::Error("colliders[" + std::to_string(i) + "].shape '" + shape +
                        "' is not plane or sphere");
    }
    out.push_back(c);
  }
  return out;
}

template <int D>
AdvanceReport advance(Particles<D>& ps, const Settings& settings, double seconds,
                      loom::Context& ctx) {
  Solver<D> solver(settings);
  return solver.advance(ps, seconds, [&](double fraction) {
    ctx.progress(fraction, 1.0, "MPM substeps");
    ctx.check_cancelled();
  });
}

struct MPMStep {
  static constexpr const char* name = "MPMStep";

  static void declare(loom::NodeSpec& s) {
    s.describe("MLS-MPM (Hu et al. 2018), quadratic B-splines, APIC: advances the particles "
               "by one frame in substeps Δt ≤ min(dt_max, cfl·Δx / (max|v| + sound speed)). "
               "The domain is [0, size]^D; particles never leave it.")
        .input<MpmState>("state", "the initial particles (from emitters); later frames get "
                                  "this node's previous output")
        .input<int>("resolution", 128, "grid cells per axis").range(8, 4096)
        .input<double>("size", 1.0, "domain edge length").range(1e-6, 1e6)
        .input<loom::Vec3>("gravity", loom::Vec3(0, -9.8, 0), "acceleration (z unused in 2D)")
        .enum_input("walls", Walls::separate,
                    {{Walls::sticky, "sticky"},
                     {Walls::slip, "slip"},
                     {Walls::separate, "separate"},
                     {Walls::open, "open"}},
                    "domain walls: sticky (v = 0), slip (no normal velocity), separate (may "
                    "leave the wall, not enter it), open (no condition; particles are still kept "
                    "inside)")
        .input<int>("wall_cells", 3, "grid nodes this close to a wall take its condition")
        .range(1, 64)
        .input<loom::json>("colliders", loom::json::array(),
                           "static colliders: [{\"shape\": \"plane\", \"point\": [x,y,z], "
                           "\"normal\": [x,y,z], \"boundary\": \"slip\"}, {\"shape\": \"sphere\", "
                           "\"center\": [x,y,z], \"radius\": r, \"boundary\": \"sticky\"}]")
        .input<double>("cfl", 0.4, "C in Δt ≤ C·Δx / (max|v| + sound speed)").range(1e-4, 1)
        .input<double>("dt_max", 1e-3, "cap on the substep (seconds)").range(1e-7, 1)
        .input<int>("max_substeps", 100000, "per frame; more is an error, not a hang")
        .at_least(1)
        .input<double>("point_radius", 0.002, "radius of each point in `points`").at_least(0)
        .input<double>("sand_friction_degrees", 30.0, "sand's friction angle φ_F without hardening")
        .range(0, 89)
        .input<bool>("sand_hardening", false,
                     "sand: φ_F = h0 + (h1 q − h3) e^{−h2 q} grows with the accumulated plastic strain q "
                     "(Klár 2016 §7.3) instead of the fixed angle")
        .input<double>("sand_h0", 35.0, "hardening: the limit angle h0 (degrees)").range(0, 89)
        .input<double>("sand_h1", 9.0, "hardening: h1 (degrees)")
        .input<double>("sand_h2", 0.2, "hardening: rate h2").at_least(0)
        .input<double>("sand_h3", 10.0, "hardening: h3 (degrees); fresh sand starts at h0 − h3")
        .output<MpmState>("state", "the particles at this frame")
        .output<loom::PointSet>("points", "positions (z = 0 in 2D), radius and colour")
        .output<int>("substeps", "substeps taken in this frame")
        .set_simulation("state", "state");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    Settings settings;
    settings.resolution = in.get<int>("resolution");
    settings.size = in.get<double>("size");
    if (!(settings.size > 0)) throw loom::Error("size must be positive");
    settings.gravity = in.get<loom::Vec3>("gravity");
    switch (in.get<Walls>("walls")) {
      case Walls::sticky: settings.walls = Boundary::sticky; break;
      case Walls::slip: settings.walls = Boundary::slip; break;
      case Walls::separate: settings.walls = Boundary::separate; break;
      case Walls::open: settings.walls_enabled = false; break;
    }
    settings.wall_cells = in.get<int>("wall_cells");
    settings.colliders = colliders_from(in.get<loom::json>("colliders"));
    settings.cfl = in.get<double>("cfl");
    settings.dt_max = in.get<double>("dt_max");
    settings.max_substeps = in.get<int>("max_substeps");
    settings.sand.friction_degrees = in.get<double>("sand_friction_degrees");
    settings.sand.hardening = in.get<bool>("sand_hardening");
    settings.sand.h0 = in.get<double>("sand_h0");
    settings.sand.h1 = in.get<double>("sand_h1");
    settings.sand.h2 = in.get<double>("sand_h2");
    settings.sand.h3 = in.get<double>("sand_h3");
    if (settings.sand.hardening && !(settings.sand.h0 - settings.sand.h3 > 0))
      throw loom::Error("sand_h0 − sand_h3 is the friction angle of fresh sand: it must be positive (h0 = " +
                        std::to_string(settings.sand.h0) + ", h3 = " + std::to_string(settings.sand.h3) + ")");

    MpmState state = in.get<MpmState>("state");
    const double seconds = ctx.time().step;
    const AdvanceReport report = state.dim == 2 ? advance(state.p2, settings, seconds, ctx)
                                                : advance(state.p3, settings, seconds, ctx);
    if (report.clamped_positions > 0)
      ctx.warn(std::to_string(report.clamped_positions) +
               " particles were outside the domain [2Δx, size − 2Δx]: moved inside");
    if (report.clamped_deformation > 0)
      ctx.warn(std::to_string(report.clamped_deformation) +
               " particle updates clamped J or a singular value of F away from zero "
               "(too large a compression for the stiffness)");
    state.time += seconds;
    state.substeps = report.substeps;
    out.set("points", point_set(state, in.get<double>("point_radius")));
    out.set("substeps", report.substeps);
    out.set("state", std::move(state));
  }
};
LOOM_NODE(MPMStep);

}  // namespace
