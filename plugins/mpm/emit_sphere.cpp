// MPMEmitSphere: fills a disk (2D) or a ball (3D) with particles.
#include "emit_inputs.hpp"
#include "loom/error.hpp"
#include "loom/plugin.hpp"

namespace {

using namespace loom::mpm;

struct MPMEmitSphere {
  static constexpr const char* name = "MPMEmitSphere";

  static void declare(loom::NodeSpec& s) {
    s.describe("Fills a disk (2D) or a ball (3D) with MPM particles, appended to `particles` "
               "when linked.");
    s.input<loom::Vec3>("center", loom::Vec3(0.5, 0.5, 0.5), "centre (domain units)")
        .input<double>("radius", 0.1, "radius").at_least(0);
    declare_emitter_inputs(s);
    s.output<MpmState>("particles", "the particles, ready for MPMStep");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const int dim = read_dimension(in);
    const EmitOptions o = read_emit_options(in, ctx);
    const loom::Vec3 c = in.get<loom::Vec3>("center");
    const double r = in.get<double>("radius");
    if (!(r > 0)) throw loom::Error("radius must be positive");
    Particles<2> p2;
    Particles<3> p3;
    if (dim == 2) {
      const Eigen::Vector2d c2 = c.head<2>();
      p2 = fill_shape<2>([&](const Eigen::Vector2d& x) { return (x - c2).squaredNorm() <= r * r; },
                         c2.array() - r, c2.array() + r, o);
    } else {
      p3 = fill_shape<3>([&](const Eigen::Vector3d& x) { return (x - c).squaredNorm() <= r * r; },
                         c.array() - r, c.array() + r, o);
    }
    out.set("particles", append_particles(in, dim, std::move(p2), std::move(p3)));
  }
};
LOOM_NODE(MPMEmitSphere);

}  // namespace
