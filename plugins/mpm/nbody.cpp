// NBody: integrates a gravitational N-body system over a duration and outputs
// the trajectories (the assignment's spaceship around a planet).
#include <cmath>
#include <vector>

#include "loom/error.hpp"
#include "loom/plugin.hpp"
#include "loom/polylines.hpp"
#include "orbits.hpp"

namespace {

using namespace loom::mpm;

struct NBody {
  static constexpr const char* name = "NBody";

  static void declare(loom::NodeSpec& s) {
    s.describe("Gravitational N-body integration, a = Σ G m r / (|r|² + ε²)^{3/2}, by "
               "symplectic leapfrog (velocity Verlet) or 4th-order Yoshida. Body 0 may be "
               "held fixed (the planet); bodies reaching `central_radius` land on it. Massless "
               "bodies (ships) attract nothing and may start at one point.")
        .set_version(2)
        .input<std::vector<double>>("masses", std::vector<double>{1.0, 0.0}, "one per body")
        .input<std::vector<loom::Vec3>>("positions",
                                        std::vector<loom::Vec3>{loom::Vec3(0, 0, 0), loom::Vec3(1, 0, 0)},
                                        "initial positions")
        .input<std::vector<loom::Vec3>>("velocities",
                                        std::vector<loom::Vec3>{loom::Vec3(0, 0, 0), loom::Vec3(0, 1, 0)},
                                        "initial velocities")
        .input<double>("G", 1.0, "gravitational constant").at_least(0)
        .input<bool>("fixed_central", true, "body 0 does not move")
        .input<double>("central_radius", 0.0, "body 0's surface: bodies reaching it land (0: none)")
        .at_least(0)
        .input<double>("softening", 0.0, "Plummer softening length ε").at_least(0)
        .enum_input("integrator", Integrator::yoshida4,
                    {{Integrator::leapfrog, "leapfrog"}, {Integrator::yoshida4, "yoshida4"}},
                    "leapfrog: 2nd order; yoshida4: 4th order (three leapfrog sub-steps)")
        .input<double>("dt", 1e-3, "time step").range(1e-9, 1e6)
        .input<double>("duration", 10.0, "time simulated").at_least(0)
        .input<int>("samples", 2000, "trajectory points per body").range(2, 1000000)
        .input<std::vector<loom::Vec3>>("colors", std::vector<loom::Vec3>{},
                                        "linear RGB per body (default: white)")
        .output<loom::Polylines>("trajectories", "one strip per body (the fixed body too)")
        .output<loom::json>("table",
                            "the trajectories as numbers: {\"time\": [t…], \"bodies\": [{\"position\": "
                            "[[x, y, z]…], \"velocity\": [[…]…]}…]} at the trajectory points")
        .output<loom::json>("events",
                            "landed bodies with their times (located inside the step), energy_error, "
                            "and each massless body's specific-energy drift (ship_energy_error)")
        .output<double>("energy_error",
                        "max |E(t) − E(0)| / |E(0)| over the run; when body 0 is the only mass, the "
                        "largest drift of a massless body's specific orbital energy about it instead");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    NBodySystem s;
    s.m = in.get<std::vector<double>>("masses");
    s.x = in.get<std::vector<loom::Vec3>>("positions");
    s.v = in.get<std::vector<loom::Vec3>>("velocities");
    s.G = in.get<double>("G");
    s.fixed_central = in.get<bool>("fixed_central");
    s.central_radius = in.get<double>("central_radius");
    s.softening = in.get<double>("softening");
    s.prepare();
    const Integrator integrator = in.get<Integrator>("integrator");
    const double duration = in.get<double>("duration"), h = in.get<double>("dt");
    const long steps = static_cast<long>(std::ceil(duration / h - 1e-9));
    if (steps > 2'000'000'000L) throw loom::Error("duration / dt exceeds 2·10⁹ steps");
    const int samples = in.get<int>("samples");
    const auto colors = in.get<std::vector<loom::Vec3>>("colors");
    const int n = s.size();

    loom::Polylines lines;
    lines.P.resize(static_cast<long>(n) * samples, 3);
    lines.C.resize(lines.P.rows(), 3);
    lines.E.resize(static_cast<long>(n) * (samples - 1), 2);
    loom::json times = loom::json::array(), bodies = loom::json::array();
    for (int b = 0; b < n; ++b) bodies.push_back({{"position", loom::json::array()}, {"velocity", loom::json::array()}});
    auto record = [&](int sample) {
      times.push_back(s.time);
      for (int b = 0; b < n; ++b) {
        const auto k = static_cast<std::size_t>(b);
        lines.P.row(static_cast<long>(b) * samples + sample) = s.x[k].transpose();
        bodies[k]["position"].push_back({s.x[k].x(), s.x[k].y(), s.x[k].z()});
        bodies[k]["velocity"].push_back({s.v[k].x(), s.v[k].y(), s.v[k].z()});
      }
    };
    EnergyDrift energy(s);
    record(0);
    int next_sample = 1;
    for (long k = 1; k <= steps; ++k) {
      step(s, std::min(h, duration - (k - 1) * h), integrator);
      energy.observe(s);
      // Samples evenly spaced in steps.
      while (next_sample < samples && k * (samples - 1) >= static_cast<long>(next_sample) * steps)
        record(next_sample++);
      if (k % 65536 == 0) {
        ctx.progress(static_cast<double>(k), static_cast<double>(steps), "N-body steps");
        ctx.check_cancelled();
      }
    }
    while (next_sample < samples) record(next_sample++);
    for (int b = 0; b < n; ++b) {
      const loom::Vec3 c = b < static_cast<int>(colors.size()) ? colors[static_cast<std::size_t>(b)] : loom::Vec3(1, 1, 1);
      for (int i = 0; i < samples; ++i) lines.C.row(static_cast<long>(b) * samples + i) = c.transpose();
      for (int i = 0; i + 1 < samples; ++i)
        lines.E.row(static_cast<long>(b) * (samples - 1) + i) << b * samples + i, b * samples + i + 1;
    }
    loom::json events = {{"landed", loom::json::array()}};
    for (int b = 0; b < n; ++b)
      if (s.landed[static_cast<std::size_t>(b)])
        events["landed"].push_back({{"body", b}, {"time", s.landed_time[static_cast<std::size_t>(b)]}});
    if (energy.ships()) {
      events["ship_energy_error"] = loom::json::array();
      for (int b = 1; b < n; ++b) events["ship_energy_error"].push_back({{"body", b}, {"error", energy.ship(b)}});
    }
    events["energy_error"] = energy.worst();
    if (!events["landed"].empty()) ctx.log("landed: " + events["landed"].dump());
    out.set("table", loom::json{{"time", std::move(times)}, {"bodies", std::move(bodies)}});
    out.set("trajectories", std::move(lines));
    out.set("events", std::move(events));
    out.set("energy_error", energy.worst());
  }
};
LOOM_NODE(NBody);

}  // namespace
