// ASAP: the as-similar-as-possible flattening in one sparse solve (Liu et al.
// 2008, eqs. 24–28), see similarity_map.hpp.
#include "loom/mesh.hpp"
#include "loom/numerics/distortion.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "loom/plugin.hpp"
#include "similarity_map.hpp"
#include "unit_square.hpp"

namespace {

struct ASAP {
  static constexpr const char* name = "ASAP";
  static void declare(loom::NodeSpec& s) {
    s.describe("As-similar-as-possible parameterization (Liu et al. 2008): each triangle maps by a "
               "similarity as closely as possible; one sparse solve.")
        .input<loom::Mesh>("mesh", "the surface to flatten")
        .input<std::vector<int>>("pins", {},
                                 "two vertices to hold, fixing the free similarity; empty: two "
                                 "far-apart vertices per connected part")
        .input<bool>("normalize", true,
                     "fit the UVs into [0,1]² (uniform scale); off keeps the mesh's scale")
        .output<loom::Mesh>("mesh", "the mesh with UVs")
        .output<loom::json>("distortion", "angle, area and ARAP distortion, flipped triangles")
        .output<std::vector<double>>("energy",
                                     "the ASAP energy (one value), at the scale of the pins");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const loom::Mesh& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    if (mesh.faces() == 0) throw loom::Error("mesh has no faces: nothing to flatten");
    const auto frames = loom::arap::triangle_frames(mesh.V, mesh.F);
    if (frames.degenerate > 0)
      ctx.warn(std::to_string(frames.degenerate) +
               " degenerate triangles (near-zero area) get small uniform weights");
    const auto pins =
        loom::arap::similarity_pins(mesh.V, mesh.F, in.get<std::vector<int>>("pins"));
    ctx.progress(0, 1, "solving");
    const auto map = loom::arap::similarity_map(frames, mesh.F, mesh.vertices(), pins,
                                                [&ctx] { ctx.check_cancelled(); });
    if (map.regularized)
      ctx.warn("the ASAP system is singular (parts joined at one vertex?): solved with a tiny "
               "diagonal shift");
    loom::Mesh result = mesh;
    result.UV = in.get<bool>("normalize")
                    ? loom::arap::fit_unit_square(
                          map.UV, loom::numerics::referenced_vertices(mesh.F, mesh.vertices()))
                    : map.UV;
    out.set("distortion", loom::numerics::to_json(loom::numerics::distortion(mesh.V, mesh.F, result.UV)));
    out.set("energy", std::vector<double>{map.energy});
    out.set("mesh", std::move(result));
    ctx.progress(1, 1, "solving");
  }
};
LOOM_NODE(ASAP);

}  // namespace
