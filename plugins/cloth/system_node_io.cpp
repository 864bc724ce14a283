#include "system_node_io.hpp"

#include <memory>

#include "cloth_state.hpp"

namespace loom::cloth {

void declare_fixing(NodeSpec& s) {
  s.input<std::vector<int>>("fixed", {}, "indices of vertices held in place")
      .input<Vec3>("fixed_box_min", Vec3(0, 0, 0),
                   "vertices inside the box [fixed_box_min, fixed_box_max] are held in place too")
      .input<Vec3>("fixed_box_max", Vec3(-1, -1, -1),
                   "upper corner of the box (an empty box, min > max, holds nothing)");
}

void apply_fixing(Inputs& in, SpringSystem& system) {
  fix_vertices(system, in.get<std::vector<int>>("fixed"), in.get<Vec3>("fixed_box_min"),
               in.get<Vec3>("fixed_box_max"));
  require_valid(system);
}

void declare_system_outputs(NodeSpec& s) {
  s.output<ClothState>("state", "the system at rest: the initial state of a ClothStep")
      .output<Mesh>("mesh", "its surface at rest");
}

void set_system_outputs(Outputs& out, SpringSystem system) {
  const ClothState state = rest_state(std::make_shared<const SpringSystem>(std::move(system)));
  out.set("mesh", state_mesh(state));
  out.set("state", state);
}

}  // namespace loom::cloth
