// Parameterize: a fixed-boundary map of a disk-topology mesh into the unit
// square (assignment 4, eq. 2-3: boundary on a convex shape, interior by
// convex combinations; Tutte 1963, Floater 1997 and 2003).
#include "harmonic_map.hpp"
#include "loom/mesh.hpp"
#include "loom/numerics/distortion.hpp"
#include "loom/plugin.hpp"

namespace {

struct Parameterize {
  static constexpr const char* name = "Parameterize";
  static void declare(loom::NodeSpec& s) {
    s.describe("Flattens a mesh with boundary into [0,1]²: the longest boundary loop on a circle or "
               "square by arc length, interior vertices by convex-combination weights (one sparse "
               "factorization, two right-hand sides). Other holes are filled for the solve.")
        .input<loom::Mesh>("mesh", "a mesh with disk topology (extra holes are filled)")
        .enum_input("boundary", loom::numerics::BoundaryShape::circle,
                    {{loom::numerics::BoundaryShape::circle, "circle"},
                     {loom::numerics::BoundaryShape::square, "square"}},
                    "where the boundary loop goes")
        .enum_input("weights", loom::parameterize::Weights::mean_value, loom::parameterize::weight_choices(),
                    "uniform (Tutte), cotangent (harmonic; may fold on obtuse triangles), cotangent_clamped "
                    "and intrinsic_delaunay (robust harmonic), mean_value (Floater 2003), shape_preserving "
                    "(Floater 1997)")
        .output<loom::Mesh>("mesh", "the input mesh with UVs")
        .output<loom::Mesh>("flattened", "the mesh laid flat: V = (u, v, 0), with UVs")
        .output<loom::json>("report", "distortion: flipped triangles, angle and area distortion, ARAP energy");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const auto& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    const auto shape = in.get<loom::numerics::BoundaryShape>("boundary");
    ctx.progress(0, 2, "solving");
    const auto p = loom::parameterize::parameterize(
        mesh.V, mesh.F, in.get<loom::parameterize::Weights>("weights"), shape,
        [&ctx] { ctx.check_cancelled(); });
    ctx.check_cancelled();
    if (p.holes_filled > 0)
      ctx.warn("mapped the longest boundary loop (" + std::to_string(p.boundary_vertices) + " vertices); " +
               std::to_string(p.holes_filled) + " other hole(s) filled for the solve");
    if (p.unreferenced > 0)
      ctx.warn(std::to_string(p.unreferenced) + " vertices are in no face: their UV is (0, 0)");
    if (p.uniform_rows > 0)
      ctx.warn(std::to_string(p.uniform_rows) +
               " vertices have only degenerate faces around them: they use uniform weights");
    ctx.progress(1, 2, "distortion");
    const auto report = loom::numerics::distortion(mesh.V, mesh.F, p.UV);
    ctx.log("solved with " + p.solver + "; " + loom::numerics::to_string(report));
    if (report.flipped > 0) ctx.warn(std::to_string(report.flipped) + " triangles are flipped or flat in UV");

    loom::Mesh with_uv = mesh;
    with_uv.UV = p.UV;
    loom::Mesh flat;
    flat.V = Eigen::MatrixX3d::Zero(mesh.V.rows(), 3);
    flat.V.leftCols<2>() = p.UV;
    flat.F = mesh.F;
    flat.UV = p.UV;
    out.set("mesh", std::move(with_uv));
    out.set("flattened", std::move(flat));
    out.set("report", loom::numerics::to_json(report));
    ctx.progress(2, 2, "distortion");
  }
};
LOOM_NODE(Parameterize);

}  // namespace
