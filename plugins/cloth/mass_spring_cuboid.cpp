// MassSpringCuboid: the assignment's soft body, a lattice of mass points with
// edge, face-diagonal and body-diagonal springs.
#include "loom/plugin.hpp"
#include "mass_spring.hpp"
#include "system_node_io.hpp"

namespace {

struct MassSpringCuboid {
  static constexpr const char* name = "MassSpringCuboid";
  static void declare(loom::NodeSpec& s) {
    s.describe("A cuboid lattice of mass points with springs along cell edges, face diagonals and "
               "body diagonals; masses lumped from the density (one eighth of each cell per "
               "corner). Its surface is the mesh output.")
        .input<loom::Vec3i>("points", loom::Vec3i(5, 5, 5), "lattice points along x, y and z").range(2, 1024)
        .input<loom::Vec3>("size", loom::Vec3(0.5, 0.5, 0.5), "edge lengths in meters").range(1e-6, 1e6)
        .input<loom::Vec3>("center", loom::Vec3(0, 1, 0), "center of the cuboid")
        .input<double>("density", 1000, "mass per volume in kg/m³").at_least(1e-12)
        .input<double>("k_edge", 1e4, "stiffness of cell-edge springs in N/m").at_least(0)
        .input<double>("k_face", 1e4, "stiffness of face-diagonal springs in N/m").at_least(0)
        .input<double>("k_body", 1e4, "stiffness of body-diagonal springs in N/m").at_least(0);
    loom::cloth::declare_fixing(s);
    loom::cloth::declare_system_outputs(s);
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const loom::Vec3i n = in.get<loom::Vec3i>("points");
    const loom::Vec3 half = in.get<loom::Vec3>("size") / 2, center = in.get<loom::Vec3>("center");
    loom::cloth::SpringSystem system = loom::cloth::cuboid_lattice(
        n.x(), n.y(), n.z(), center - half, center + half, in.get<double>("density"),
        in.get<double>("k_edge"), in.get<double>("k_face"), in.get<double>("k_body"));
    loom::cloth::apply_fixing(in, system);
    loom::cloth::set_system_outputs(out, std::move(system));
  }
};
LOOM_NODE(MassSpringCuboid);

}  // namespace
