// SmoothMesh: the smoothing flows the displacement-map denoising is compared
// with (uniform Laplacian and cotangent / mean-curvature smoothing).
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "mesh_denoising.hpp"
#include "loom/numerics/tangent_frames.hpp"

namespace {

struct SmoothMesh {
  static constexpr const char* name = "SmoothMesh";
  static void declare(loom::NodeSpec& s) {
    s.describe("Explicit smoothing: `steps` times p_i += λ (Σ w_ij p_j / Σ w_ij − p_i), uniform "
               "(Laplacian smoothing) or cotangent weights (mean-curvature flow, clamped at 0), "
               "boundary fixed.")
        .input<loom::Mesh>("mesh", "the mesh to smooth")
        .enum_input("weights", loom::shading::SmoothingWeights::uniform,
                    {{loom::shading::SmoothingWeights::uniform, "uniform"},
                     {loom::shading::SmoothingWeights::cotangent, "cotangent"}},
                    "edge weights")
        .input<int>("steps", 5, "iterations").range(0, 100000)
        .input<double>("lambda", 0.5, "step size").range(0, 1)
        .output<loom::Mesh>("mesh", "the smoothed mesh (normals recomputed)");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const loom::Mesh& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    const auto weights = in.get<loom::shading::SmoothingWeights>("weights");
    loom::Mesh result = mesh;
    const int steps = in.get<int>("steps");
    for (int s = 0; s < steps; ++s) {
      ctx.check_cancelled();
      ctx.progress(s, steps, "smoothing");
      result.V = loom::shading::smooth(result.V, result.F, weights, 1, in.get<double>("lambda"));
    }
    result.N = loom::numerics::vertex_normals(result.V, result.F);
    out.set("mesh", std::move(result));
  }
};
LOOM_NODE(SmoothMesh);

}  // namespace
