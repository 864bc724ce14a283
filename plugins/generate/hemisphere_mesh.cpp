// HemisphereMesh: the upper half of a sphere, optionally with radial noise.
#include "generators.hpp"
#include "loom/plugin.hpp"

namespace {

struct HemisphereMesh {
  static constexpr const char* name = "HemisphereMesh";
  static void declare(loom::NodeSpec& s) {
    s.describe("The hemisphere z >= 0 of a sphere, pole at the top, one boundary loop on the equator. "
               "noise > 0 moves each vertex radially by up to ±noise·radius (seeded by the graph seed).")
        .input<double>("radius", 1.0, "radius").range(1e-9, 1e9)
        .input<int>("rings", 16, "rings of vertices from the pole to the equator").range(1, 4096)
        .input<int>("segments", 64, "vertices per ring").range(3, 65536)
        .input<double>("noise", 0.0, "relative radial noise").range(0, 0.5)
        .output<loom::Mesh>("mesh", "the hemisphere");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    out.set("mesh", loom::generate::hemisphere_mesh(in.get<double>("radius"), in.get<int>("rings"),
                                                    in.get<int>("segments"), in.get<double>("noise"), ctx.rng(),
                                                    [&ctx] { ctx.check_cancelled(); }));
  }
};
LOOM_NODE(HemisphereMesh);

}  // namespace
