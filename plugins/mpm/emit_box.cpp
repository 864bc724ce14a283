// MPMEmitBox: fills an axis-aligned box with particles of one material.
#include "emit_inputs.hpp"
#include "loom/plugin.hpp"

namespace {

using namespace loom::mpm;

struct MPMEmitBox {
  static constexpr const char* name = "MPMEmitBox";

  static void declare(loom::NodeSpec& s) {
    s.describe("Fills the box [min, max] with MPM particles (2D uses x and y), appended to "
               "`particles` when linked.");
    s.input<loom::Vec3>("min", loom::Vec3(0.2, 0.2, 0.2), "lower corner (domain units)")
        .input<loom::Vec3>("max", loom::Vec3(0.4, 0.4, 0.4), "upper corner");
    declare_emitter_inputs(s);
    s.output<MpmState>("particles", "the particles, ready for MPMStep");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const int dim = read_dimension(in);
    const EmitOptions o = read_emit_options(in, ctx);
    const loom::Vec3 lo = in.get<loom::Vec3>("min"), hi = in.get<loom::Vec3>("max");
    Particles<2> p2;
    Particles<3> p3;
    if (dim == 2)
      p2 = fill_shape<2>([](const Eigen::Vector2d&) { return true; }, lo.head<2>(), hi.head<2>(), o);
    else
      p3 = fill_shape<3>([](const Eigen::Vector3d&) { return true; }, lo, hi, o);
    out.set("particles", append_particles(in, dim, std::move(p2), std::move(p3)));
  }
};
LOOM_NODE(MPMEmitBox);

}  // namespace
