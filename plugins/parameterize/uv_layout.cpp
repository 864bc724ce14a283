// UVLayout: a picture of a mesh's UVs in the unit square.
#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "uv_layout_drawing.hpp"

namespace {

struct UVLayout {
  static constexpr const char* name = "UVLayout";
  static void declare(loom::NodeSpec& s) {
    s.describe("Draws the UV layout: every triangle's edges in the unit square (v up), flipped "
               "triangles filled red.")
        .input<loom::Mesh>("mesh", "a mesh with UVs")
        .input<int>("size", 1024, "width and height in pixels").range(16, 16384)
        .output<loom::Image>("image", "the layout, RGB, sRGB-tagged");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const auto& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    if (!mesh.has_uv()) throw loom::Error("the mesh has no UVs: run Parameterize first");
    out.set("image", loom::Image(loom::parameterize::draw_uv_layout(mesh.UV, mesh.F, in.get<int>("size")),
                                 loom::Encoding::srgb));
  }
};
LOOM_NODE(UVLayout);

}  // namespace
