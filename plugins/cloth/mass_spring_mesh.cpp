// MassSpringMesh: springs on the edges of any triangle mesh, and across its
// interior edges for bending.
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "mass_spring.hpp"
#include "system_node_io.hpp"

namespace {

struct MassSpringMesh {
  static constexpr const char* name = "MassSpringMesh";
  static void declare(loom::NodeSpec& s) {
    s.describe("A mass-spring system from a triangle mesh: a structural spring on every edge, a "
               "bending spring across every interior edge (between the two opposite vertices); "
               "masses lumped from the area density (one third of each triangle per corner).")
        .input<loom::Mesh>("mesh", "the surface; its positions are the rest state")
        .input<double>("area_density", 0.1, "mass per area in kg/m²").at_least(1e-12)
        .input<double>("k_edge", 1e5, "stiffness of edge springs in N/m").at_least(0)
        .input<double>("k_bend", 1e4, "stiffness of bending springs in N/m (0: none)").at_least(0);
    loom::cloth::declare_fixing(s);
    loom::cloth::declare_system_outputs(s);
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const loom::Mesh& mesh = in.get<loom::Mesh>("mesh");
    loom::require_valid(mesh, "mesh");
    if (mesh.faces() == 0) throw loom::Error("mesh has no triangles: there are no springs to build");
    loom::cloth::SpringSystem system = loom::cloth::mesh_springs(
        mesh.V, mesh.F, in.get<double>("area_density"), in.get<double>("k_edge"), in.get<double>("k_bend"));
    loom::cloth::apply_fixing(in, system);
    loom::cloth::set_system_outputs(out, std::move(system));
  }
};
LOOM_NODE(MassSpringMesh);

}  // namespace
