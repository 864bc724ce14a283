// GridMesh: a planar rectangle of squares split into triangles, with UVs.
#include "loom/mesh.hpp"
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
    const loom::Vec2 size = in.get<loom::Vec2>("size");
    const int nx = in.get<loom::Vec2i>("resolution").x(), ny = in.get<loom::Vec2i>("resolution").y();
    loom::Mesh mesh;
    mesh.V.resize((nx + 1) * (ny + 1), 3);
    mesh.UV.resize(mesh.V.rows(), 2);
    mesh.F.resize(2 * nx * ny, 3);
    auto index = [&](int i, int j) { return j * (nx + 1) + i; };
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const double u = static_cast<double>(i) / nx, v = static_cast<double>(j) / ny;
        mesh.V.row(index(i, j)) << (u - 0.5) * size.x(), (v - 0.5) * size.y(), 0;
        mesh.UV.row(index(i, j)) << u, v;
      }
    int f = 0;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        mesh.F.row(f++) << index(i, j), index(i + 1, j), index(i + 1, j + 1);
        mesh.F.row(f++) << index(i, j), index(i + 1, j + 1), index(i, j + 1);
      }
    out.set("mesh", std::move(mesh));
  }
};
LOOM_NODE(GridMesh);

}  // namespace
