// ARAP: as-rigid-as-possible flattening by local/global iteration (Liu et al.
// 2008, §5), the cotangent system factored once, see local_global.hpp.
#include <limits>

#include "local_global.hpp"
#include "loom/hash.hpp"
#include "loom/mesh.hpp"
#include "loom/numerics/distortion.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "loom/partial_pacing.hpp"
#include "loom/plugin.hpp"
#include "similarity_map.hpp"
#include "tutte_map.hpp"
#include "unit_square.hpp"

namespace {

enum class Init { asap, tutte, given };
enum class Model { arap, hybrid };

struct ARAP {
  static constexpr const char* name = "ARAP";
  static void declare(loom::NodeSpec& s) {
    s.describe("As-rigid-as-possible parameterization (Liu et al. 2008): local/global iteration; "
               "local step fits a rotation per triangle (2x2 SVD, in parallel), global step "
               "back-substitutes with the once-factored cotangent system.")
        .input<loom::Mesh>("mesh", "the surface to flatten")
        .enum_input("init", Init::asap, {{Init::asap, "asap"}, {Init::tutte, "tutte"}, {Init::given, "given"}},
                    "initial map: ASAP, uniform Tutte (needs a boundary), or the mesh's own UVs")
        .input<int>("iterations", 100, "maximal number of local/global iterations").range(0, 100000)
        .input<double>("tolerance", 1e-6,
                       "stop when an iteration lowers the energy by less than this fraction")
        .at_least(0)
        .input<int>("pin", -1, "vertex held at its initial UV; -1: the first vertex of each part")
        .at_least(-1)
        .enum_input("model", Model::arap, {{Model::arap, "arap"}, {Model::hybrid, "hybrid"}},
                    "arap: rotations; hybrid: the paper's ASAP/ARAP blend with weight lambda")
        .input<double>("lambda", 1.0,
                       "hybrid weight of (a²+b²−1)²: small is nearly ASAP, large nearly ARAP")
        .at_least(0)
        .input<bool>("normalize", true,
                     "fit the UVs into [0,1]² (uniform scale); off keeps the mesh's scale")
        .output<loom::Mesh>("mesh", "the mesh with UVs")
        .output<loom::json>("distortion", "angle, area and ARAP distortion, flipped triangles")
        .output<std::vector<double>>("energy",
                                     "ARAP energy of the initial map, then per iteration (before "
                                     "normalize)");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const loom::Mesh& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    if (mesh.faces() == 0) throw loom::Error("mesh has no faces: nothing to flatten");
    const int n = mesh.vertices();
    const int pin = in.get<int>("pin");
    if (pin >= n)
      throw loom::Error("pin " + std::to_string(pin) + " is not a vertex (the mesh has " +
                        std::to_string(n) + ")");
    loom::arap::ArapOptions options;
    options.max_iterations = in.get<int>("iterations");
    options.tolerance = in.get<double>("tolerance");
    if (in.get<Model>("model") == Model::hybrid) {
      options.lambda = in.get<double>("lambda");
      if (options.lambda == 0)
        throw loom::Error("lambda = 0 is ASAP, which one pin cannot hold in place: use the ASAP "
                          "node, or a lambda above 0");
    }

    // The factored system depends on the mesh and the pin only: reruns with
    // other iterations, tolerance, model or initialization reuse it.
    loom::Hasher key;
    key.bytes(mesh.V.data(), sizeof(double) * mesh.V.size())
        .bytes(mesh.F.data(), sizeof(int) * mesh.F.size())
        .pod(pin);
    ctx.progress(0, 1, "factoring");
    const auto check = [&ctx] { ctx.check_cancelled(); };
    const auto system = ctx.scratch<loom::arap::ArapSystem>(key.digest(), [&] {
      return std::make_shared<loom::arap::ArapSystem>(loom::arap::arap_system(
          mesh.V, mesh.F, pin >= 0 ? std::vector<int>{pin} : std::vector<int>{}, check));
    });
    if (system->frames.degenerate > 0)
      ctx.warn(std::to_string(system->frames.degenerate) +
               " degenerate triangles (near-zero area) get small uniform weights");

    const Init init = in.get<Init>("init");
    Eigen::MatrixX2d UV0;
    if (init == Init::given) {
      if (!mesh.has_uv())
        throw loom::Error("init is 'given' but the mesh has no UVs: link a parameterized mesh, "
                          "or choose asap or tutte");
      if (!mesh.UV.allFinite()) throw loom::Error("the mesh's UVs have NaN or infinite values");
      UV0 = mesh.UV;
    } else if (init == Init::tutte) {
      UV0 = loom::arap::tutte_map(mesh.V, mesh.F);
    } else {
      UV0 = loom::arap::similarity_map(system->frames, mesh.F, n,
                                       loom::arap::similarity_pins(mesh.V, mesh.F, {}), check)
                .UV;
    }

    // The map as the output gives it: fitted into the unit square, or as is.
    const bool normalize = in.get<bool>("normalize");
    const auto with_uv = [&](const Eigen::MatrixX2d& UV) {
      loom::Mesh flat = mesh;
      flat.UV = normalize ? loom::arap::fit_unit_square(UV, loom::numerics::referenced_vertices(mesh.F, n)) : UV;
      return flat;
    };
    loom::PartialPacing pacing;  // for whoever watches: the map so far, as the iterations go
    const auto result = loom::arap::arap(*system, UV0, options, [&](int k, double, const Eigen::MatrixX2d& UV) {
      ctx.progress(k, options.max_iterations, "iterating");
      ctx.check_cancelled();
      if (ctx.partial_wanted() && pacing.due()) {
        pacing.published();
        ctx.publish_partial("mesh", [&] { return with_uv(UV); },
                            {double(k), double(options.max_iterations), "iterations", -1});
      }
    });
    if (!result.converged && options.max_iterations > 0)
      ctx.log("ARAP stopped at the iteration cap (" + std::to_string(options.max_iterations) +
              ") before the tolerance was met");
    ctx.check_cancelled();
    loom::Mesh flat = with_uv(result.UV);
    out.set("distortion", loom::numerics::to_json(loom::numerics::distortion(mesh.V, mesh.F, flat.UV)));
    out.set("energy", result.energy);
    out.set("mesh", std::move(flat));
  }
};
LOOM_NODE(ARAP);

}  // namespace
