// DiskMesh: a triangulated disk, flat or with bumps, one boundary loop.
#include "generators.hpp"
#include "loom/plugin.hpp"

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
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    out.set("mesh", loom::generate::disk_mesh(in.get<double>("radius"), in.get<int>("rings"),
                                              in.get<int>("segments"), in.get<double>("bump_height"),
                                              [&ctx] { ctx.check_cancelled(); }));
  }
};
LOOM_NODE(DiskMesh);

}  // namespace
