// MinimalSurface: interior vertices moved to satisfy the discrete Laplace
// equation δ_i = Σ_j w_ij (x_j - x_i) = 0 with every boundary loop fixed
// (assignment 4, eq. 1; Pinkall and Polthier 1993 for the cotangent weights).
#include "harmonic_map.hpp"
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"

namespace {

struct MinimalSurface {
  static constexpr const char* name = "MinimalSurface";
  static void declare(loom::NodeSpec& s) {
    s.describe("Moves interior vertices so that each is the weighted average of its neighbours "
               "(δ_i = 0), boundary fixed: a discrete minimal surface spanning the boundary.")
        .input<loom::Mesh>("mesh", "a mesh with at least one boundary loop")
        .enum_input("weights", loom::parameterize::Weights::cotangent,
                    {{loom::parameterize::Weights::uniform, "uniform"},
                     {loom::parameterize::Weights::cotangent, "cotangent"},
                     {loom::parameterize::Weights::intrinsic_delaunay, "intrinsic_delaunay"}},
                    "uniform (membrane of the graph) or cotangent (area-minimizing)")
        .input<int>("iterations", 1, "cotangent only: recompute weights on the new surface and solve again")
        .range(1, 100)
        .output<loom::Mesh>("mesh", "the same connectivity with interior vertices moved");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const auto& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    ctx.progress(0, 1, "solving");
    loom::numerics::FixedBoundarySolve last;
    loom::Mesh result = mesh;
    result.V = loom::parameterize::minimal_surface(
        mesh.V, mesh.F, in.get<loom::parameterize::Weights>("weights"),
        in.get<int>("iterations"), &last);
    result.N.resize(0, 3);  // the old normals no longer fit the surface
    if (last.uniform_rows > 0)
      ctx.warn(std::to_string(last.uniform_rows) +
               " vertices have only degenerate faces around them: they use uniform weights");
    ctx.log("solved with " + last.solver);
    ctx.progress(1, 1, "solving");
    out.set("mesh", std::move(result));
  }
};
LOOM_NODE(MinimalSurface);

}  // namespace
