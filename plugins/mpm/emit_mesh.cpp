// MPMEmitMesh: fills the inside of a closed triangle mesh (3D) with particles.
#include <tbb/parallel_for.h>

#include "emit_inputs.hpp"
#include "loom/error.hpp"
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"

namespace {

using namespace loom::mpm;

struct MPMEmitMesh {
  static constexpr const char* name = "MPMEmitMesh";

  static void declare(loom::NodeSpec& s) {
    s.describe("Fills the inside of a closed triangle mesh with 3D MPM particles (inside: "
               "generalized winding number > 1/2), placed by `translate` and `scale`.");
    s.input<loom::Mesh>("mesh", "a closed triangle mesh")
        .input<loom::Vec3>("translate", loom::Vec3(0.5, 0.5, 0.5), "where the mesh's origin goes")
        .input<double>("scale", 0.2, "uniform scale applied first").at_least(0);
    declare_emitter_inputs(s);
    s.output<MpmState>("particles", "the particles, ready for MPMStep");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    if (read_dimension(in) != 3) throw loom::Error("a mesh fills 3D particles: set dimension 3");
    const loom::Mesh& mesh = in.get<loom::Mesh>("mesh");
    if (mesh.faces() == 0) throw loom::Error("the mesh has no faces");
    const double scale = in.get<double>("scale");
    if (!(scale > 0)) throw loom::Error("scale must be positive");
    Eigen::MatrixX3d V = mesh.V * scale;
    V.rowwise() += in.get<loom::Vec3>("translate").transpose();
    if (!V.allFinite()) throw loom::Error("the mesh has non-finite vertices");
    const EmitOptions o = read_emit_options(in, ctx);
    const Eigen::Vector3d lo = V.colwise().minCoeff(), hi = V.colwise().maxCoeff();
    auto inside = [&](const Eigen::Vector3d& x) { return winding_number(V, mesh.F, x) > 0.5; };
    Particles<3> p3 = fill_shape<3>(inside, lo, hi, o);
    out.set("particles", append_particles(in, 3, Particles<2>(), std::move(p3)));
  }
};
LOOM_NODE(MPMEmitMesh);

}  // namespace
