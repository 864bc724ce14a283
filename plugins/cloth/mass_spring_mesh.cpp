// MassSpringMesh: springs on the edges of any triangle mesh, and across its
// interior edges for bending.
#include "loom/mesh.hpp"
#include "loom/numerics/rotation.hpp"
#include "loom/plugin.hpp"
#include "mass_spring.hpp"
#include "system_node_io.hpp"

namespace {

struct MassSpringMesh {
  static constexpr const char* name = "MassSpringMesh";
  static void declare(loom::NodeSpec& s) {
    s.describe("A mass-spring system from a triangle mesh: a structural spring on every edge, a "
               "bending spring across every interior edge (between the two opposite vertices); "
               "masses lumped from the area density (one third of each triangle per corner). The "
               "mesh is placed (rotate_degrees, then translate) before the fixed vertices are chosen; "
               "its UVs and colors follow the vertices into every state's mesh.")
        .input<loom::Mesh>("mesh", "the surface; its positions, placed, are the rest state")
        .input<loom::Vec3>("translate", loom::Vec3(0, 0, 0), "moves the mesh (after rotating it), in meters")
        .input<loom::Vec3>("rotate_degrees", loom::Vec3(0, 0, 0),
                           "rotates the mesh about its origin: about x, then y, then z (fixed axes)")
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
    const Eigen::Matrix3d R = loom::numerics::rotation_from_degrees(in.get<loom::Vec3>("rotate_degrees"));
    const Eigen::MatrixX3d placed = (mesh.V * R.transpose()).rowwise() + in.get<loom::Vec3>("translate").transpose();
    loom::cloth::SpringSystem system = loom::cloth::mesh_springs(
        placed, mesh.F, in.get<double>("area_density"), in.get<double>("k_edge"), in.get<double>("k_bend"));
    if (mesh.has_uv()) system.UV = mesh.UV;
    if (mesh.has_colors()) system.C = mesh.C;
    loom::cloth::apply_fixing(in, system);
    loom::cloth::set_system_outputs(out, std::move(system));
  }
};
LOOM_NODE(MassSpringMesh);

}  // namespace
