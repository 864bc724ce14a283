// MassSpringGrid: the assignment's cloth, a grid with structural, shear and
// bending springs, hanging as a curtain or lying flat.
#include <string>

#include "loom/numerics/rotation.hpp"
#include "loom/plugin.hpp"
#include "mass_spring.hpp"
#include "system_node_io.hpp"

namespace {

enum class Plane { vertical, horizontal };
enum class Pin { none, top_edge, top_corners };

struct MassSpringGrid {
  static constexpr const char* name = "MassSpringGrid";
  static void declare(loom::NodeSpec& s) {
    s.describe("A grid cloth of mass points: structural springs between neighbours, shear springs "
               "on square diagonals, bending springs two vertices apart; masses lumped from the "
               "area density. Hangs in the x-y plane (curtain) or lies in the x-z plane, turned by "
               "rotate_degrees about its center; UVs span [0,1]² (v up the curtain), as GridMesh's.")
        .input<loom::Vec2i>("vertices", loom::Vec2i(20, 20), "grid vertices along u and v").range(2, 4096)
        .input<loom::Vec2>("size", loom::Vec2(1, 1), "width and height in meters").range(1e-6, 1e6)
        .input<loom::Vec3>("center", loom::Vec3(0, 1, 0), "center of the cloth")
        .input<loom::Vec3>("rotate_degrees", loom::Vec3(0, 0, 0),
                           "rotates the cloth about its center: about x, then y, then z (fixed axes)")
        .enum_input("plane", Plane::vertical, {{Plane::vertical, "vertical"}, {Plane::horizontal, "horizontal"}},
                    "vertical: u along x, v up along y; horizontal: u along x, v along -z")
        .input<double>("area_density", 0.1, "mass per area in kg/m²").at_least(1e-12)
        .input<double>("k_structural", 1e5, "stiffness of neighbour springs in N/m").at_least(0)
        .input<double>("k_shear", 1e5, "stiffness of diagonal springs in N/m").at_least(0)
        .input<double>("k_bend", 1e5, "stiffness of springs two vertices apart in N/m").at_least(0)
        .enum_input("pin", Pin::top_edge,
                    {{Pin::none, "none"}, {Pin::top_edge, "top_edge"}, {Pin::top_corners, "top_corners"}},
                    "vertices held in place: the last row (the top of a curtain), its two ends, or none");
    loom::cloth::declare_fixing(s);
    loom::cloth::declare_system_outputs(s);
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const loom::Vec2i n = in.get<loom::Vec2i>("vertices");
    const loom::Vec2 size = in.get<loom::Vec2>("size");
    const Eigen::Matrix3d R = loom::numerics::rotation_from_degrees(in.get<loom::Vec3>("rotate_degrees"));
    const Eigen::Vector3d u = R * Eigen::Vector3d(size.x(), 0, 0);
    const Eigen::Vector3d v = R * (in.get<Plane>("plane") == Plane::vertical ? Eigen::Vector3d(0, size.y(), 0)
                                                                              : Eigen::Vector3d(0, 0, -size.y()));
    const Eigen::Vector3d origin = in.get<loom::Vec3>("center") - (u + v) / 2;
    loom::cloth::SpringSystem system = loom::cloth::grid_cloth(
        n.x(), n.y(), origin, u, v, in.get<double>("area_density"), in.get<double>("k_structural"),
        in.get<double>("k_shear"), in.get<double>("k_bend"));
    const Pin pin = in.get<Pin>("pin");
    for (int i = 0; i < n.x(); ++i)
      if (pin == Pin::top_edge || (pin == Pin::top_corners && (i == 0 || i == n.x() - 1)))
        system.fixed[loom::cloth::grid_index(n.x(), i, n.y() - 1)] = 1;
    loom::cloth::apply_fixing(in, system);
    loom::cloth::set_system_outputs(out, std::move(system));
  }
};
LOOM_NODE(MassSpringGrid);

}  // namespace
