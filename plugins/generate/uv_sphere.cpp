// UVSphere: a closed sphere of latitude rings and longitude segments.
#include "generators.hpp"
#include "loom/plugin.hpp"

namespace {

struct UVSphere {
  static constexpr const char* name = "UVSphere";
  static void declare(loom::NodeSpec& s) {
    s.describe("A closed sphere (no boundary): two poles and rings-1 latitude rings, outward normals.")
        .input<double>("radius", 1.0, "radius").range(1e-9, 1e9)
        .input<int>("rings", 16, "latitude bands").range(2, 4096)
        .input<int>("segments", 32, "longitude segments").range(3, 65536)
        .output<loom::Mesh>("mesh", "the sphere");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    out.set("mesh", loom::generate::uv_sphere_mesh(in.get<double>("radius"), in.get<int>("rings"),
                                                   in.get<int>("segments"), [&ctx] { ctx.check_cancelled(); }));
  }
};
LOOM_NODE(UVSphere);

}  // namespace
