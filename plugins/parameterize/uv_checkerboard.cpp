// UVCheckerboard: the mesh rendered with a checkerboard texture through its
// UVs, so stretch and folds show at a glance.
#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "uv_raster.hpp"

namespace {

struct UVCheckerboard {
  static constexpr const char* name = "UVCheckerboard";
  static void declare(loom::NodeSpec& s) {
    s.describe("Renders the mesh (orthographic, z-buffered, simple shading) textured with a "
               "checkerboard through its UVs.")
        .input<loom::Mesh>("mesh", "a mesh with UVs")
        .input<int>("cells", 16, "checker squares per unit of UV").range(1, 1024)
        .input<int>("size", 512, "width and height in pixels").range(16, 8192)
        .input<double>("azimuth", -60.0, "view direction around z, degrees")
        .input<double>("elevation", 40.0, "view direction above the xy plane, degrees").range(-90, 90)
        .output<loom::Image>("image", "the render, RGB, sRGB-tagged");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const auto& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    if (!mesh.has_uv()) throw loom::Error("the mesh has no UVs: run Parameterize first");
    out.set("image", loom::Image(loom::parameterize::render_checkered(
                                     mesh.V, mesh.F, mesh.UV, in.get<int>("size"), in.get<int>("cells"),
                                     in.get<double>("azimuth"), in.get<double>("elevation")),
                                 loom::Encoding::srgb));
  }
};
LOOM_NODE(UVCheckerboard);

}  // namespace
