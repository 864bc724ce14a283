// MeshNoise: seeded Gaussian noise along the vertex normals, to make the
// denoising input from a clean generated surface.
#include <random>

#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "loom/numerics/tangent_frames.hpp"

namespace {

struct MeshNoise {
  static constexpr const char* name = "MeshNoise";
  static void declare(loom::NodeSpec& s) {
    s.describe("Moves every vertex along its normal by Gaussian noise of standard deviation sigma "
               "(seeded by the graph seed and the node id).")
        .input<loom::Mesh>("mesh", "the clean mesh")
        .input<double>("sigma", 0.005, "standard deviation, scene units").range(0, 1e9)
        .output<loom::Mesh>("mesh", "the noisy mesh (normals recomputed)");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const loom::Mesh& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    const Eigen::MatrixX3d N = loom::numerics::vertex_normals(mesh.V, mesh.F);
    std::normal_distribution<double> gauss(0, in.get<double>("sigma"));
    auto& rng = ctx.rng();
    loom::Mesh result = mesh;
    for (int i = 0; i < mesh.vertices(); ++i) {
      if (i % 65536 == 0) ctx.check_cancelled();
      result.V.row(i) += gauss(rng) * N.row(i);
    }
    ctx.check_cancelled();
    result.N = loom::numerics::vertex_normals(result.V, result.F);
    out.set("mesh", std::move(result));
  }
};
LOOM_NODE(MeshNoise);

}  // namespace
