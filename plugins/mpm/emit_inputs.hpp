// The inputs every emitter node shares (material, sampling, velocity, colour,
// the state to append to) and their typed reading.
#pragma once

#include <memory>

#include "emitters.hpp"
#include "loom/node.hpp"
#include "mpm_state.hpp"

namespace loom::mpm {

// Declares: particles (optional, to append to), dimension, material, E, nu,
// density, velocity, color, sampling, spacing, count, particle_volume.
void declare_emitter_inputs(NodeSpec& s);
EmitOptions read_emit_options(Inputs& in, Context& ctx);
// The dimension asked for, checked against the state appended to.
int read_dimension(Inputs& in);
// A copy of the input state (or an empty one of `dim`) with `added` appended.
MpmState append_particles(Inputs& in, int dim, Particles<2>&& added2, Particles<3>&& added3);

}  // namespace loom::mpm
