// GridMesh: a planar rectangle of squares split into triangles, with UVs.
#include "generators.hpp"
#include "loom/plugin.hpp"

namespace {

struct GridMesh {
  static constexpr const char* name = "GridMesh";
  static void declare(loom::NodeSpec& s) {
    s.describe("A planar grid in z = 0, centered at the origin, with UVs spanning [0,1]².")
        .input<loom::Vec2>("size", loom::Vec2(1, 1), "width and height").range(1e-9, 1e9)
        .input<loom::Vec2i>("resolution", loom::Vec2i(10, 10), "squares along x and y").range(1, 4096)
        .output<loom::Mesh>("mesh", "the grid");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const loom::Vec2i resolution = in.get<loom::Vec2i>("resolution");
    out.set("mesh", loom::generate::rectangle_mesh(in.get<loom::Vec2>("size"), resolution.x(), resolution.y()));
  }
};
LOOM_NODE(GridMesh);

}  // namespace
