// Denoise: removes a displacement map's heights along the normals
// (p_i - d_i n_i, the assignment's eq. 45 applied).
#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "mesh_denoising.hpp"
#include "loom/numerics/tangent_frames.hpp"

namespace {

struct Denoise {
  static constexpr const char* name = "Denoise";
  static void declare(loom::NodeSpec& s) {
    s.describe("Moves each vertex by −d_i n_i, d_i = offset + scale * map(uv_i) read bilinearly from a "
               "displacement map (DisplacementFromNoise), n_i the area-weighted vertex normal.")
        .input<loom::Mesh>("mesh", "the noisy mesh with UVs")
        .input<loom::Image>("displacement", "the map, first channel")
        .input<double>("scale", 1.0, "d = offset + scale * map")
        .input<double>("offset", 0.0, "d = offset + scale * map")
        .input<double>("strength", 1.0, "fraction of d removed").range(-10, 10)
        .output<loom::Mesh>("mesh", "the denoised mesh (normals recomputed)");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const loom::Mesh& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    if (!mesh.has_uv()) throw loom::Error("mesh has no UVs: the displacement map lives in UV space");
    if (!mesh.UV.allFinite()) throw loom::Error("mesh has non-finite UVs");
    const loom::Image& image = in.get<loom::Image>("displacement");
    if (image.empty()) throw loom::Error("displacement is empty");
    loom::require_finite(image, "displacement");
    const double scale = in.get<double>("scale"), offset = in.get<double>("offset");
    if (!std::isfinite(scale) || !std::isfinite(offset)) throw loom::Error("scale and offset must be finite");
    loom::shading::DisplacementMap map;
    if (image.channels() == 1)
      map.image = image.pixels;
    else
      cv::extractChannel(image.pixels, map.image, 0);
    map.scale = scale;
    map.offset = offset;
    const Eigen::MatrixX3d N = loom::numerics::vertex_normals(mesh.V, mesh.F);
    const Eigen::VectorXd d = in.get<double>("strength") * loom::shading::sample_displacement(map, mesh.UV);
    loom::Mesh result = mesh;
    result.V = loom::shading::remove_displacement(mesh.V, N, d);
    result.N = loom::numerics::vertex_normals(result.V, result.F);
    out.set("mesh", std::move(result));
  }
};
LOOM_NODE(Denoise);

}  // namespace
