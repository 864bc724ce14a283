// HemisphereMesh: the upper half of a sphere, optionally with radial noise.
#include <cmath>
#include <random>

#include "loom/plugin.hpp"
#include "polar_mesh.hpp"

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
    const double R = in.get<double>("radius"), noise = in.get<double>("noise");
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    out.set("mesh", loom::generate::polar_mesh(
                        in.get<int>("rings"), in.get<int>("segments"), [&](double t, double phi) {
                          const double theta = t * M_PI / 2;  // polar angle from the pole
                          const double r = R * (1 + noise * u(ctx.rng()));
                          return Eigen::Vector3d(r * std::sin(theta) * std::cos(phi),
                                                 r * std::sin(theta) * std::sin(phi), r * std::cos(theta));
                        }));
  }
};
LOOM_NODE(HemisphereMesh);

}  // namespace
