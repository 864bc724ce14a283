// What the three system-building nodes share: the inputs that fix vertices
// and the outputs (initial state and rest mesh).
#pragma once

#include "loom/node.hpp"
#include "mass_spring.hpp"

namespace loom::cloth {

// Declares "fixed" (IntList), "fixed_box_min" and "fixed_box_max" (Vec3).
void declare_fixing(NodeSpec& s);
// Marks the vertices those inputs select; validates the system.
void apply_fixing(Inputs& in, SpringSystem& system);
// Declares the outputs "state" (ClothState, at rest) and "mesh".
void declare_system_outputs(NodeSpec& s);
void set_system_outputs(Outputs& out, SpringSystem system);

}  // namespace loom::cloth
