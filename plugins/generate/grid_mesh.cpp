// GridMesh: a planar rectangle of squares split into triangles, with UVs.
#include "generators.hpp"
#include "loom/numerics/rotation.hpp"
#include "loom/plugin.hpp"

namespace {

struct GridMesh {
  static constexpr const char* name = "GridMesh";
  static void declare(loom::NodeSpec& s) {
    s.describe("A planar grid with UVs spanning [0,1]²: made in z = 0 about the origin, then turned by "
               "rotate_degrees and moved to center.")
        .input<loom::Vec2>("size", loom::Vec2(1, 1), "width and height").range(1e-9, 1e9)
        .input<loom::Vec2i>("resolution", loom::Vec2i(10, 10), "squares along x and y").range(1, 4096)
        .input<loom::Vec3>("center", loom::Vec3(0, 0, 0), "where the grid's center goes")
        .input<loom::Vec3>("rotate_degrees", loom::Vec3(0, 0, 0),
                           "rotates the grid about its center: about x, then y, then z (fixed axes)")
        .output<loom::Mesh>("mesh", "the grid");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const loom::Vec2i resolution = in.get<loom::Vec2i>("resolution");
    loom::Mesh mesh = loom::generate::rectangle_mesh(in.get<loom::Vec2>("size"), resolution.x(), resolution.y(),
                                                     [&ctx] { ctx.check_cancelled(); });
    ctx.check_cancelled();
    const Eigen::Matrix3d R = loom::numerics::rotation_from_degrees(in.get<loom::Vec3>("rotate_degrees"));
    mesh.V = (mesh.V * R.transpose()).rowwise() + in.get<loom::Vec3>("center").transpose();
    out.set("mesh", std::move(mesh));
  }
};
LOOM_NODE(GridMesh);

}  // namespace
