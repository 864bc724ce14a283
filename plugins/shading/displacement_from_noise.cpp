// DisplacementFromNoise: the noise of a mesh along its normals as a
// displacement map in UV space (the assignment's eqs. 44-45).
#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "mesh_denoising.hpp"
#include "loom/numerics/tangent_frames.hpp"

namespace {

struct DisplacementFromNoise {
  static constexpr const char* name = "DisplacementFromNoise";
  static void declare(loom::NodeSpec& s) {
    s.describe("Eqs. 44-45: δ_i = p_i − mean of its neighbours, d_i = <δ_i, n_i> (0 on the boundary), "
               "baked into a displacement map in the mesh's UV space (each texel: inverse-distance "
               "average of its K nearest vertices in UV), scaled to [0, 1]: d = offset + scale * map.")
        .input<loom::Mesh>("mesh", "a noisy mesh with UVs")
        .input<int>("size", 512, "map width and height in texels").range(2, 8192)
        .input<int>("neighbors", 4, "K: vertices averaged per texel").range(1, 64)
        .output<loom::Image>("image", "displacement in [0, 1], one channel, linear")
        .output<double>("scale", "d = offset + scale * image")
        .output<double>("offset", "d = offset + scale * image");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const loom::Mesh& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    if (mesh.faces() == 0) throw loom::Error("mesh has no faces");
    if (!mesh.has_uv()) throw loom::Error("mesh has no UVs: parameterize it first (e.g. Parameterize)");
    if (!mesh.UV.allFinite()) throw loom::Error("mesh has non-finite UVs");
    const Eigen::MatrixX3d N = loom::numerics::vertex_normals(mesh.V, mesh.F);
    const Eigen::VectorXd d = loom::shading::normal_displacements(mesh.V, mesh.F, N);
    ctx.progress(0.3, 1, "baking");
    const auto map = loom::shading::bake_displacement(mesh.UV, d, in.get<int>("size"), in.get<int>("neighbors"));
    out.set("image", loom::Image(map.image, loom::Encoding::linear));
    out.set("scale", map.scale);
    out.set("offset", map.offset);
  }
};
LOOM_NODE(DisplacementFromNoise);

}  // namespace
