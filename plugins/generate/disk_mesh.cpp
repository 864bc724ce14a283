// DiskMesh: a triangulated disk, flat or with bumps, one boundary loop.
#include <cmath>

#include "loom/plugin.hpp"
#include "polar_mesh.hpp"

namespace {

struct DiskMesh {
  static constexpr const char* name = "DiskMesh";
  static void declare(loom::NodeSpec& s) {
    s.describe("A disk in the xy plane on a polar grid; bump_height > 0 lifts it to "
               "z = h sin(2πx/R) sin(2πy/R) (1 - r²/R²), a bumpy disk with a flat circular boundary.")
        .input<double>("radius", 1.0, "radius R").range(1e-9, 1e9)
        .input<int>("rings", 16, "rings of vertices").range(1, 4096)
        .input<int>("segments", 64, "vertices per ring").range(3, 65536)
        .input<double>("bump_height", 0.0, "height h of the bumps")
        .output<loom::Mesh>("mesh", "the disk");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const double R = in.get<double>("radius"), h = in.get<double>("bump_height");
    out.set("mesh", loom::generate::polar_mesh(
                        in.get<int>("rings"), in.get<int>("segments"), [&](double t, double phi) {
                          const double x = R * t * std::cos(phi), y = R * t * std::sin(phi);
                          const double z = h * std::sin(2 * M_PI * x / R) * std::sin(2 * M_PI * y / R) * (1 - t * t);
                          return Eigen::Vector3d(x, y, z);
                        }));
  }
};
LOOM_NODE(DiskMesh);

}  // namespace
